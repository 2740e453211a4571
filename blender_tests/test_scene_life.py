"""What happens to a painted scene over its life: saving, reloading, undoing, converting, exporting, rendering."""

import json

import bpy
import numpy as np
import worldpaint_engine as engine
from scene_kit import hills_terrain, irregular_terrain, prototypes, select_only, slope_exemplar, top_camera
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

EXEMPLAR = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (100.0, 100.0)}
DESTINATION = {"region_mode": 'RECT', "rect_min": (0.0, 100.0), "rect_max": (200.0, 200.0)}


def painted_scene():
    terrain_obj, examples, data = slope_exemplar()
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Slope forest", **EXEMPLAR) == {'FINISHED'}
    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=4, **DESTINATION) == {'FINISHED'}
    return terrain_obj, examples, data


def point_counts():
    return {c: len(o.data.vertices) for c, o in point_cloud_objects(bpy.context.scene).items()}


def test_palette_and_points_survive_save_and_reload(tmp_path):
    painted_scene()
    settings = bpy.context.scene.worldpaint
    saved_json = [c.json for c in settings.palette]
    saved_preview = settings.palette[0].preview_image
    counts = point_counts()
    path = str(tmp_path / "painted.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert len(bpy.context.scene.worldpaint.palette) == 0
    bpy.ops.wm.open_mainfile(filepath=path)

    settings = bpy.context.scene.worldpaint
    assert [c.json for c in settings.palette] == saved_json
    assert settings.palette[0].name == "Slope forest"
    assert settings.terrain is not None and settings.terrain.name == "Terrain"
    image = bpy.data.images[saved_preview]
    assert image.packed_file is not None and tuple(image.size) == (64, 64)
    assert point_counts() == counts
    instanced = sum(1 for i in bpy.context.evaluated_depsgraph_get().object_instances
                    if i.is_instance and i.parent is not None and i.parent.original.get("wp_points"))
    assert instanced == sum(counts.values())
    # the reloaded palette still pastes
    select_only([])
    region = {"region_mode": 'CIRCLE', "circle_center": (150.0, 50.0), "circle_radius": 20.0}
    assert bpy.ops.worldpaint.paste_color(seed=9, **region) == {'FINISHED'}


# In background mode Blender's window manager does not push an undo step after an operator marked UNDO the way the
# UI does; the tests push it themselves (ed.undo_push after the operator, exactly what the UI does for an UNDO
# operator), then check that one undo restores the scene.

def test_undo_restores_the_scene_before_a_paste():
    painted_scene()
    counts = point_counts()
    n_objects = len(bpy.data.objects)
    bpy.ops.ed.undo_push(message="before second paste")
    select_only([])
    bpy.ops.worldpaint.paste_color(seed=11, region_mode='RECT', rect_min=(100.0, 0.0), rect_max=(200.0, 100.0))
    bpy.ops.ed.undo_push(message="Paste Color")
    assert point_counts() != counts
    bpy.ops.ed.undo()
    assert point_counts() == counts
    assert len(bpy.data.objects) == n_objects


def test_undo_restores_the_scene_before_learning_and_converting():
    terrain_obj, examples, _ = slope_exemplar()
    bpy.ops.ed.undo_push(message="exemplar built")
    select_only(examples)
    bpy.ops.worldpaint.learn_color(**EXEMPLAR)
    bpy.ops.ed.undo_push(message="Learn Color")
    assert len(bpy.context.scene.worldpaint.palette) == 1
    bpy.ops.ed.undo()
    assert len(bpy.context.scene.worldpaint.palette) == 0

    select_only([o for o in bpy.data.collections["Examples"].objects])
    bpy.ops.worldpaint.learn_color(**EXEMPLAR)
    select_only([])
    bpy.ops.worldpaint.paste_color(seed=1, **DESTINATION)
    n_objects = len(bpy.data.objects)
    counts = point_counts()
    bpy.ops.ed.undo_push(message="pasted")
    bpy.ops.worldpaint.convert_to_objects(category="Rock")
    bpy.ops.ed.undo_push(message="Convert to Objects")
    assert len(bpy.data.objects) == n_objects - 1 + counts["Rock"]
    bpy.ops.ed.undo()
    assert len(bpy.data.objects) == n_objects and point_counts() == counts


def test_operators_that_change_data_are_undoable():
    for op in ("learn_color", "paste_color", "clear_region", "convert_to_objects", "import_palette"):
        assert 'UNDO' in getattr(bpy.types, f"WORLDPAINT_OT_{op}").bl_options, op


def test_convert_to_objects_makes_one_real_object_per_point():
    painted_scene()
    n_objects = len(bpy.data.objects)
    co, rotation, scale, _ = point_cloud_arrays(point_cloud_objects(bpy.context.scene)["Tree"])
    assert bpy.ops.worldpaint.convert_to_objects(category="Tree") == {'FINISHED'}
    made = bpy.data.collections["WP_Tree objects"].objects
    assert len(made) == len(co)
    assert "Tree" not in point_cloud_objects(bpy.context.scene)
    assert len(bpy.data.objects) == n_objects - 1 + len(co)
    assert all(o.instance_type == 'COLLECTION' and o.instance_collection.name == "Tree" for o in made)
    locations = np.array([o.location for o in made])
    np.testing.assert_allclose(np.sort(locations[:, 0]), np.sort(co[:, 0]), atol=1e-4)


def test_export_and_import_palette_round_trip(tmp_path):
    painted_scene()
    path = tmp_path / "palette.json"
    saved = [c.json for c in bpy.context.scene.worldpaint.palette]
    assert bpy.ops.worldpaint.export_palette(filepath=str(path)) == {'FINISHED'}
    document = json.loads(path.read_text())
    assert document["version"] == engine.PALETTE_FORMAT_VERSION and len(document["colors"]) == 1

    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert bpy.ops.worldpaint.import_palette(filepath=str(path)) == {'FINISHED'}
    settings = bpy.context.scene.worldpaint
    assert [c.name for c in settings.palette] == ["Slope forest"]
    assert json.loads(settings.palette[0].json) == json.loads(saved[0])
    assert bpy.data.images.get(settings.palette[0].preview_image) is not None
    assert {c.name for c in settings.categories} == {"Tree", "Rock", "Grass"}


def test_paste_on_hills_and_an_irregular_mesh_sits_on_the_surface():
    _, examples, _ = slope_exemplar()
    select_only(examples)
    bpy.ops.worldpaint.learn_color(**EXEMPLAR)
    color = bpy.context.scene.worldpaint.palette[0].json
    for make, region in ((hills_terrain, (30.0, 30.0, 90.0, 90.0)), (irregular_terrain, (10.0, 10.0, 90.0, 90.0))):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        prototypes()
        terrain_obj = make()
        settings = bpy.context.scene.worldpaint
        settings.terrain = terrain_obj
        entry = settings.palette.add()
        entry.name, entry.json = "Slope forest", color
        rect = {"region_mode": 'RECT', "rect_min": region[:2], "rect_max": region[2:]}
        assert bpy.ops.worldpaint.paste_color(seed=5, **rect) == {'FINISHED'}, make.__name__
        depsgraph = bpy.context.evaluated_depsgraph_get()
        errors = []
        for inst in depsgraph.object_instances:
            if inst.is_instance and inst.parent is not None and inst.parent.original.get("wp_points"):
                t = inst.matrix_world.translation
                hit, where, *_ = terrain_obj.ray_cast((t.x, t.y, 1000.0), (0.0, 0.0, -1.0))
                assert hit
                errors.append(abs(t.z - where.z))
        assert len(errors) == sum(point_counts().values()) > 0, make.__name__
        assert max(errors) < 0.01, f"{make.__name__}: worst height error {max(errors):.4f} m"
        # the points themselves carry the engine's height of its heightfield, close to the surface already
        for co, *_ in (point_cloud_arrays(o) for o in point_cloud_objects(bpy.context.scene).values()):
            for x, y, z in co[:50]:
                hit, where, *_ = terrain_obj.ray_cast((x, y, 1000.0), (0.0, 0.0, -1.0))
                assert abs(z - where.z) < 0.1


def test_workbench_render_shows_the_instances(tmp_path):
    painted_scene()
    scene = bpy.context.scene
    # hide the hand-made examples: the picture shows only the pasted half
    bpy.context.view_layer.layer_collection.children["Examples"].exclude = True
    top_camera((100.0, 150.0), 200.0, 200.0)
    scene.render.engine = 'BLENDER_WORKBENCH'
    scene.display.shading.color_type = 'MATERIAL'
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 160, 120, 100
    scene.render.filepath = str(tmp_path / "render.png")
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(str(tmp_path / "render.png"))
    pixels = np.empty(160 * 120 * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    rgb = pixels.reshape(-1, 4)[:, :3].copy()
    assert rgb.std(axis=0).max() > 0.02, "the frame is flat"
    tree_green = (rgb[:, 1] > rgb[:, 0] + 0.1) & (rgb[:, 1] > rgb[:, 2] + 0.1)
    assert tree_green.mean() > 0.002, "no tree-coloured pixels in the frame"

    # the same frame without the point clouds: what differs is what the instancer drew
    for obj in point_cloud_objects(scene).values():
        obj.hide_render = True
    bpy.ops.render.render(write_still=True)
    image.reload()
    image.pixels.foreach_get(pixels)
    bare = pixels.reshape(-1, 4)[:, :3]
    assert ((bare[:, 1] > bare[:, 0] + 0.1) & (bare[:, 1] > bare[:, 2] + 0.1)).mean() < tree_green.mean() / 5
    drawn = np.abs(rgb - bare).max(axis=1) > 0.05
    assert drawn.mean() > 0.01, f"instances cover only {drawn.mean():.2%} of the frame"


def test_a_moved_rotated_and_scaled_terrain_is_used_in_world_space():
    _, examples, _ = slope_exemplar()
    select_only(examples)
    bpy.ops.worldpaint.learn_color(**EXEMPLAR)
    color = bpy.context.scene.worldpaint.palette[0].json
    bpy.ops.wm.read_factory_settings(use_empty=True)
    prototypes()
    terrain_obj = hills_terrain(size=80.0)
    terrain_obj.location = (500.0, -200.0, 40.0)
    terrain_obj.rotation_euler = (0.0, 0.0, 0.4)
    terrain_obj.scale = (1.5, 1.5, 1.2)
    settings = bpy.context.scene.worldpaint
    settings.terrain = terrain_obj
    entry = settings.palette.add()
    entry.name, entry.json = "Slope forest", color
    bpy.context.scene.cursor.location = (540.0, -150.0, 0.0)
    assert bpy.ops.worldpaint.paste_color(seed=3, region_mode='CIRCLE', circle_center=(540.0, -150.0),
                                          circle_radius=30.0) == {'FINISHED'}
    depsgraph = bpy.context.evaluated_depsgraph_get()
    inverse = terrain_obj.matrix_world.inverted()
    errors = []
    for inst in depsgraph.object_instances:
        if inst.is_instance and inst.parent is not None and inst.parent.original.get("wp_points"):
            t = inst.matrix_world.translation
            assert (t.x - 540.0) ** 2 + (t.y + 150.0) ** 2 <= 30.0**2 + 1e-6
            # cast in the terrain's own space: down in world is down in its space (rotation about Z only)
            origin = inverse @ t.copy()
            origin.z += 1000.0
            hit, where, *_ = terrain_obj.ray_cast(origin, (0.0, 0.0, -1.0))
            assert hit
            errors.append(abs(t.z - (terrain_obj.matrix_world @ where).z))
    assert errors and max(errors) < 0.01, f"worst height error {max(errors):.4f} m"
