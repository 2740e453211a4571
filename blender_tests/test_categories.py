"""Categories come from what the artist placed: instanced collections, linked duplicates, or a wp_category tag."""

import bpy
import numpy as np
import worldpaint_engine
from scene_kit import engine_terrain_object, mesh_object, select_only
from worldpaint.bridge import engine
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

SQUARE = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (60.0, 60.0)}
DESTINATION = {"region_mode": 'RECT', "rect_min": (60.0, 0.0), "rect_max": (120.0, 60.0)}


def flat_world():
    terrain = engine.terrain_from_grid((0.0, 0.0), 2.0, np.zeros((61, 61)))
    obj = engine_terrain_object("Flat", terrain)
    bpy.context.scene.worldpaint.terrain = obj
    return obj


def linked_duplicates(mesh_name, positions):
    source = mesh_object(mesh_name, [(0, 0, 0), (0.5, 0, 0), (0, 0.5, 0), (0, 0, 1)], [(0, 1, 2), (0, 1, 3)])
    source.data.name = mesh_name
    made = [source]
    for _ in positions[1:]:
        dup = source.copy()
        bpy.context.scene.collection.objects.link(dup)
        made.append(dup)
    for obj, (x, y) in zip(made, positions, strict=True):
        obj.location = (float(x), float(y), 0.0)
    return made


def test_linked_duplicates_are_a_category_instanced_from_a_hidden_prototype_collection():
    flat_world()
    pts = engine.exemplar_hard_core({"shape": "rect", "min": [0, 0], "max": [60, 60]}, 0.03, 3.0, 2)
    bushes = linked_duplicates("Bush", pts)
    select_only(bushes)
    assert bpy.ops.worldpaint.learn_color(name="Bushes", **SQUARE) == {'FINISHED'}
    assert [c.name for c in bpy.context.scene.worldpaint.categories] == ["Bush"]
    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=1, **DESTINATION) == {'FINISHED'}

    cloud = point_cloud_objects(bpy.context.scene)["Bush"]
    proto = bpy.data.collections["WP_proto_Bush"]
    assert [o.data.name for o in proto.objects] == ["Bush"]
    assert proto.name not in bpy.context.scene.collection.children, "the prototype collection stays out of sight"
    n = len(cloud.data.vertices)
    assert abs(n - len(pts)) <= 0.15 * len(pts)
    instanced = [i for i in bpy.context.evaluated_depsgraph_get().object_instances
                 if i.is_instance and i.parent is not None and i.parent.original == cloud]
    assert len(instanced) == n

    bpy.ops.worldpaint.convert_to_objects(category="Bush")
    made = bpy.data.collections["WP_Bush objects"].objects
    assert len(made) == n and all(o.data.name == "Bush" for o in made), "converted to linked duplicates"


def test_wp_category_tags_objects_of_any_kind():
    flat_world()
    pts = engine.exemplar_uniform({"shape": "rect", "min": [0, 0], "max": [60, 60]}, 0.02, 4)
    markers = []
    for k, (x, y) in enumerate(pts):
        obj = bpy.data.objects.new(f"Marker{k}", None)
        obj["wp_category"] = "Beacon"
        obj.location = (float(x), float(y), 0.0)
        bpy.context.scene.collection.objects.link(obj)
        markers.append(obj)
    select_only(markers)
    assert bpy.ops.worldpaint.find_categories() == {'FINISHED'}
    assert [c.name for c in bpy.context.scene.worldpaint.categories] == ["Beacon"]
    assert bpy.ops.worldpaint.learn_color(**SQUARE) == {'FINISHED'}
    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=2, **DESTINATION) == {'FINISHED'}
    assert len(point_cloud_objects(bpy.context.scene)["Beacon"].data.vertices) > 0


def test_category_layer_and_priority_are_editable_and_learned():
    flat_world()
    region = {"shape": "rect", "min": [0, 0], "max": [60, 60]}
    big = linked_duplicates("Boulder", engine.exemplar_hard_core(region, 0.01, 5.0, 1))
    small = linked_duplicates("Pebble", engine.exemplar_uniform(region, 0.03, 2))
    select_only(big + small)
    bpy.ops.worldpaint.find_categories()
    settings = bpy.context.scene.worldpaint
    pebble = settings.categories["Pebble"]
    boulder = settings.categories["Boulder"]
    pebble.priority, boulder.priority = 0, 5
    pebble.layer = "ground"
    bpy.ops.worldpaint.learn_color(name="Stones", **SQUARE)
    learned = {c["name"]: c for c in worldpaint_engine.color_summary(settings.palette["Stones"].json)["categories"]}
    assert learned["Pebble"]["priority"] == 0 and learned["Boulder"]["priority"] == 5
    assert learned["Pebble"]["layer"] == "ground"


def test_remove_color():
    flat_world()
    pts = engine.exemplar_uniform({"shape": "rect", "min": [0, 0], "max": [60, 60]}, 0.02, 4)
    select_only(linked_duplicates("Bush", pts))
    bpy.ops.worldpaint.learn_color(name="A", **SQUARE)
    bpy.ops.worldpaint.learn_color(name="B", **SQUARE)
    image = bpy.context.scene.worldpaint.palette["A"].preview_image
    bpy.ops.worldpaint.remove_color(index=0)
    assert [c.name for c in bpy.context.scene.worldpaint.palette] == ["B"]
    assert bpy.data.images.get(image) is None


def test_paste_next_to_hand_placed_content_respects_the_spacing_across_the_border():
    """Region of influence: a hard-core color pasted beside its own exemplar leaves no pair too close at the seam."""
    flat_world()
    region = {"shape": "rect", "min": [0, 0], "max": [60, 60]}
    pts = engine.exemplar_hard_core(region, 0.04, 3.0, 5)
    examples = linked_duplicates("Stone", pts)
    select_only(examples)
    bpy.ops.worldpaint.learn_color(name="Stones", **SQUARE)
    (learned,) = worldpaint_engine.color_summary(bpy.context.scene.worldpaint.palette[0].json)["categories"]
    min_distance = learned["min_distance"]
    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=3, **DESTINATION) == {'FINISHED'}
    pasted = point_cloud_arrays(point_cloud_objects(bpy.context.scene)["Stone"])[0][:, :2]
    near_seam = pasted[pasted[:, 0] < 60.0 + 2 * min_distance]
    examples_near = pts[pts[:, 0] > 60.0 - 2 * min_distance]
    gaps = np.hypot(*(near_seam[:, None, :] - examples_near[None, :, :]).transpose(2, 0, 1))
    assert len(near_seam) and gaps.min() >= 0.95 * min_distance, f"closest pair across the seam {gaps.min():.2f} m"
