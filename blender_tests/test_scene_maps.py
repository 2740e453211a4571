"""Maps made in the scene, learned and followed as a user would: a forest where a weight-painted group is high, reeds
near the water of a collection, each pasted on ground painted or laid out differently."""

import bpy
import numpy as np
import pytest
from scene_kit import collection_instances, flat_terrain, poly_curve, prototypes, select_only
from worldpaint.bridge import engine, scene_maps
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

EXEMPLAR = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (100.0, 100.0)}
DESTINATION = {"region_mode": 'RECT', "rect_min": (140.0, 0.0), "rect_max": (240.0, 100.0)}


def ground():
    terrain_obj = flat_terrain("Ground", size=(240.0, 100.0), cell=2.0)
    bpy.context.scene.worldpaint.terrain = terrain_obj
    prototypes()
    return terrain_obj


def paint_group(terrain_obj, name, high):
    """A vertex group of weight 1 where ``high(x, y)`` holds and 0 elsewhere, as weight painting leaves it."""
    group = terrain_obj.vertex_groups.new(name=name)
    co = np.array([v.co[:2] for v in terrain_obj.data.vertices])
    group.add([int(i) for i in np.flatnonzero(high(co[:, 0], co[:, 1]))], 1.0, 'REPLACE')
    group.add([int(i) for i in np.flatnonzero(~high(co[:, 0], co[:, 1]))], 0.0, 'REPLACE')
    return group


def pasted(category):
    return point_cloud_arrays(point_cloud_objects(bpy.context.scene)[category])[0]


def test_a_forest_learned_on_a_painted_group_follows_the_group_painted_differently():
    terrain_obj = ground()
    # the example: trees where the west half of the example is painted; the destination is painted in its north half
    paint_group(terrain_obj, "Moisture", lambda x, y: np.where(x < 100.0, x < 50.0, y > 50.0))
    xy = engine.exemplar_hard_core({"shape": "rect", "min": [0.0, 0.0], "max": [50.0, 100.0]}, 0.02, 3.0, 4)
    select_only(collection_instances("Tree", xy, np.zeros(len(xy))))
    assert "group:Moisture" in dict(scene_maps.available(terrain_obj))
    assert bpy.ops.worldpaint.learn_color(name="Wet forest", maps="group:Moisture", **EXEMPLAR) == {'FINISHED'}
    entry = bpy.context.scene.worldpaint.palette["Wet forest"]
    assert ("Tree", "group:Moisture") in {(i.category, i.other) for i in entry.interactions}

    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=3, **DESTINATION) == {'FINISHED'}
    trees = pasted("Tree")
    wet = trees[:, 1] > 51.0  # the painted half, past the one cell where the weight is interpolated
    print(f"\n{len(trees)} trees pasted ({len(xy)} in the example), {wet.mean():.1%} where the group is high")
    assert wet.mean() >= 0.8
    assert abs(len(trees) - len(xy)) <= 0.25 * len(xy), "the painted area is as large as the example's"

    # a terrain that lost the group cannot be painted with the color: a clear error, the scene as it was
    terrain_obj.vertex_groups.remove(terrain_obj.vertex_groups["Moisture"])
    with pytest.raises(RuntimeError, match="Moisture"):
        bpy.ops.worldpaint.paste_color(seed=4, **DESTINATION)
    assert len(pasted("Tree")) == len(trees)


def distance_histogram(distances):
    counts, _ = np.histogram(np.minimum(distances, 29.9), bins=np.arange(0.0, 32.5, 2.5))
    return counts / counts.sum()


def test_reeds_learned_near_water_keep_their_distance_to_other_water():
    ground()
    water = bpy.data.collections.new("Water")
    bpy.context.scene.collection.children.link(water)
    # a stream across the example, and one running north-south through the destination
    poly_curve("Stream", [(-10.0, 30.0), (110.0, 30.0)], collection=water)
    poly_curve("River", [(190.0, -10.0), (190.0, 110.0)], collection=water)
    rng = np.random.default_rng(5)
    distance = np.minimum(np.abs(rng.normal(0.0, 6.0, 220)), 25.0)
    xy = np.column_stack([rng.uniform(0.0, 100.0, 220), 30.0 + distance * rng.choice([-1.0, 1.0], 220)])
    select_only(collection_instances("Grass", xy, np.zeros(len(xy))))
    assert bpy.ops.worldpaint.learn_color(name="Reeds", maps="distance:Water", **EXEMPLAR) == {'FINISHED'}

    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=3, **DESTINATION) == {'FINISHED'}
    reeds = pasted("Grass")
    learned = distance_histogram(np.abs(xy[:, 1] - 30.0))
    painted = distance_histogram(np.abs(reeds[:, 0] - 190.0))
    tv = 0.5 * np.abs(learned - painted).sum()
    print(f"\n{len(reeds)} reeds pasted ({len(xy)} in the example); distance histogram TV {tv:.3f}")
    assert tv <= 0.15
    assert 0.6 * len(xy) <= len(reeds) <= 1.4 * len(xy)


def test_a_scene_map_that_is_not_there_is_a_clear_error():
    ground()
    xy = engine.exemplar_hard_core({"shape": "rect", "min": [0.0, 0.0], "max": [50.0, 100.0]}, 0.02, 3.0, 4)
    select_only(collection_instances("Tree", xy, np.zeros(len(xy))))
    for maps, message in (("group:Nope", "no vertex group 'Nope'"), ("distance:Nowhere", "No collection"),
                          ("moisture", "is not a map")):
        with pytest.raises(RuntimeError, match=message):
            bpy.ops.worldpaint.learn_color(maps=maps, **EXEMPLAR)
    assert len(bpy.context.scene.worldpaint.palette) == 0


def test_attributes_and_images_are_read_at_the_terrain_where_they_were_painted():
    terrain_obj = ground()
    mesh = terrain_obj.data
    # a face attribute: 1 on faces west of x = 60; a color attribute of the corners: grey 0.5
    wet = mesh.attributes.new("wet", 'FLOAT', 'FACE')
    centres = np.array([p.center[:2] for p in mesh.polygons])
    wet.data.foreach_set("value", (centres[:, 0] < 60.0).astype(np.float32))
    tint = mesh.color_attributes.new("tint", 'FLOAT_COLOR', 'CORNER')
    tint.data.foreach_set("color", np.tile([0.5, 0.5, 0.5, 1.0], len(mesh.loops)).astype(np.float32))
    # an image through the UVs: white on the image's northern half
    uv = mesh.uv_layers.new(name="UVMap")
    corners = np.array([mesh.vertices[loop.vertex_index].co[:2] for loop in mesh.loops])
    uv.data.foreach_set("uv", (corners / [240.0, 100.0]).ravel().astype(np.float32))
    image = bpy.data.images.new("Mask", 64, 64)
    pixels = np.zeros((64, 64, 4), dtype=np.float32)
    pixels[32:, :, :] = 1.0
    image.pixels.foreach_set(pixels.ravel())
    material = terrain_obj.data.materials[0]
    material.use_nodes = True
    material.node_tree.nodes.new('ShaderNodeTexImage').image = image

    offered = dict(scene_maps.available(terrain_obj))
    assert {"attribute:wet", "attribute:tint", "image:Mask"} <= set(offered)
    assert "attribute:UVMap" not in offered and "attribute:position" not in offered
    from worldpaint.bridge import terrain
    heightfield = terrain.engine_terrain(bpy.context, terrain_obj, ["attribute:wet", "attribute:tint", "image:Mask"])
    points = np.array([[20.0, 20.0], [120.0, 20.0], [20.0, 80.0], [120.0, 80.0]])
    assert np.allclose(heightfield.map_at("attribute:wet", points), [1.0, 0.0, 1.0, 0.0], atol=1e-6)
    assert np.allclose(heightfield.map_at("attribute:tint", points), 0.5, atol=1e-3)
    assert np.allclose(heightfield.map_at("image:Mask", points), [0.0, 0.0, 1.0, 1.0], atol=1e-6)


def test_the_distance_to_painted_instances_is_measured_from_where_they_stand():
    terrain_obj = ground()
    xy = engine.exemplar_hard_core({"shape": "rect", "min": [0.0, 0.0], "max": [50.0, 100.0]}, 0.02, 3.0, 4)
    select_only(collection_instances("Rock", xy, np.zeros(len(xy))))
    assert bpy.ops.worldpaint.learn_color(name="Rocks", **EXEMPLAR) == {'FINISHED'}
    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=3, **DESTINATION) == {'FINISHED'}
    rocks_cloud = point_cloud_objects(bpy.context.scene)["Rock"]
    rocks = pasted("Rock")[:, :2]
    collection = bpy.data.collections.new("Pasted rocks")
    bpy.context.scene.collection.children.link(collection)
    collection.objects.link(rocks_cloud)
    from worldpaint.bridge import terrain
    heightfield = terrain.engine_terrain(bpy.context, terrain_obj, ["distance:Pasted rocks"])
    probes = np.array([[150.0, 20.0], [190.0, 50.0], [230.0, 80.0], [60.0, 50.0]])
    exact = np.linalg.norm(probes[:, None, :] - rocks[None, :, :], axis=2).min(axis=1)
    measured = heightfield.map_at("distance:Pasted rocks", probes)
    assert np.abs(measured - exact).max() <= 1.5, (measured, exact)  # within a 2 m grid's rounding
