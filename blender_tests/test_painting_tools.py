"""The painting tools through their operators, as a script or a user drives them: brush, eraser, pipette, move,
stretch, gradient, blur and the palette's management. Each is one undo step."""

import json

import bpy
import numpy as np
import pytest
import worldpaint_engine as engine
from scene_kit import flat_terrain, hard_core_examples, prototypes, select_only
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

EXAMPLE_CORNER, EXAMPLE_SIZE = (0.0, 140.0), 60.0
EXAMPLE = {"region_mode": 'RECT', "rect_min": EXAMPLE_CORNER,
           "rect_max": (EXAMPLE_CORNER[0] + EXAMPLE_SIZE, EXAMPLE_CORNER[1] + EXAMPLE_SIZE)}


def forest(density=0.04, name="Forest", seed=3):
    """A flat 300 × 200 m terrain with a hand-placed hard-core example (3 m) in a corner, learned as a color."""
    prototypes()
    terrain_obj = flat_terrain()
    bpy.context.scene.worldpaint.terrain = terrain_obj
    examples = hard_core_examples("Tree", EXAMPLE_CORNER, EXAMPLE_SIZE, density, 3.0, seed)
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name=name, **EXAMPLE) == {'FINISHED'}
    select_only([])
    return engine.color_summary(bpy.context.scene.worldpaint.palette[name].json)["categories"][0]


def trees():
    clouds = point_cloud_objects(bpy.context.scene)
    return point_cloud_arrays(clouds["Tree"])[0] if "Tree" in clouds else np.zeros((0, 3))


def stroke(points):
    return [{"name": "", "location": (float(x), float(y), 0.0)} for x, y in points]


def closest_pair(xy):
    if len(xy) < 2:
        return np.inf
    d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
    d[np.diag_indices(len(xy))] = np.inf
    return d.min()


def distance_to_path(xy, path):
    a, b = path[:-1], path[1:]
    ab = b - a
    t = np.clip(((xy[:, None, :] - a) * ab).sum(-1) / (ab * ab).sum(-1), 0.0, 1.0)
    return np.linalg.norm(xy[:, None, :] - (a + t[..., None] * ab), axis=-1).min(axis=1)


def paste(rect_min, rect_max, seed=1, color=""):
    assert bpy.ops.worldpaint.paste_color(color=color, seed=seed, region_mode='RECT', rect_min=rect_min,
                                          rect_max=rect_max) == {'FINISHED'}


def test_a_brush_stroke_paints_the_color_along_its_path_in_one_undo_step():
    tree = forest()
    path = np.column_stack([np.linspace(70.0, 265.0, 40), np.full(40, 70.0)])
    bpy.ops.ed.undo_push(message="before the stroke")
    # 40 dabs: a dab every 5 m (half the 10 m radius) over 195 m
    assert bpy.ops.worldpaint.brush(stroke=stroke(path), radius=10.0, seed=2) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="WorldPaint Brush")
    xy = trees()[:, :2]
    assert len(xy) > 0 and distance_to_path(xy, path).max() <= 10.0 + 1e-3
    assert closest_pair(xy) >= tree["min_distance"] - 1e-6, "no pair closer than the example's across dab borders"
    inner = (xy[:, 0] > 80.0) & (xy[:, 0] < 255.0) & (np.abs(xy[:, 1] - 70.0) < 8.0)
    ratio = inner.sum() / (175.0 * 16.0 * tree["density"])
    assert abs(ratio - 1.0) <= 0.15, f"density along the stroke {ratio:.2f} of the color's"
    bpy.ops.ed.undo()
    assert len(trees()) == 0


def test_an_alpha_brush_paints_half_the_density():
    tree = forest()
    settings = bpy.context.scene.worldpaint
    settings.brush_opacity = 0.5
    path = np.column_stack([np.linspace(70.0, 265.0, 60), np.full(60, 70.0)])
    assert bpy.ops.worldpaint.brush(stroke=stroke(path), radius=15.0, seed=4) == {'FINISHED'}
    xy = trees()[:, :2]
    inner = (xy[:, 0] > 85.0) & (xy[:, 0] < 250.0) & (np.abs(xy[:, 1] - 70.0) < 15.0)
    ratio = inner.sum() / (165.0 * 30.0 * tree["density"])
    assert abs(ratio - 0.5) <= 0.12, f"opacity 0.5 painted {ratio:.2f} of the color's density"


def test_the_eraser_removes_points_near_its_path_only_and_undo_restores_them():
    forest()
    paste((60.0, 20.0), (260.0, 120.0))
    before = trees()
    path = np.array([[80.0, 70.0], [240.0, 70.0]])
    bpy.ops.ed.undo_push(message="pasted")
    assert bpy.ops.worldpaint.erase(stroke=stroke(path), radius=12.0) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="WorldPaint Eraser")
    after = trees()
    near = distance_to_path(before[:, :2], path) <= 12.0
    assert near.sum() > 20
    assert len(after) == (~near).sum()
    np.testing.assert_allclose(np.sort(after[:, 0]), np.sort(before[~near][:, 0]))
    bpy.ops.ed.undo()
    assert len(trees()) == len(before)


def test_the_eraser_keeps_other_categories_and_hand_placed_objects():
    forest()
    rocks = hard_core_examples("Rock", EXAMPLE_CORNER, EXAMPLE_SIZE, 0.01, 4.0, 9)
    trees_and_rocks = [o for o in bpy.context.scene.objects if o.instance_collection is not None]
    select_only(trees_and_rocks)
    assert bpy.ops.worldpaint.learn_color(name="Mixed", **EXAMPLE) == {'FINISHED'}
    select_only([])
    paste((60.0, 20.0), (260.0, 120.0), color="Mixed")
    clouds = point_cloud_objects(bpy.context.scene)
    n_trees, n_rocks = (len(clouds[c].data.vertices) for c in ("Tree", "Rock"))
    assert bpy.ops.worldpaint.erase(stroke=stroke([(80.0, 70.0), (240.0, 70.0)]), radius=12.0,
                                    category="Rock") == {'FINISHED'}
    assert len(clouds["Tree"].data.vertices) == n_trees
    assert 0 < len(clouds["Rock"].data.vertices) < n_rocks
    # sweeping over the hand-placed example erases nothing of it
    assert bpy.ops.worldpaint.erase(stroke=stroke([(0.0, 170.0), (60.0, 170.0)]), radius=30.0) == {'FINISHED'}
    assert all(o.name in bpy.context.scene.objects for o in trees_and_rocks) and len(rocks) > 10


def test_the_pipette_picks_what_stands_under_it_and_undo_removes_the_color():
    forest(density=0.04)
    paste((60.0, 20.0), (260.0, 120.0))
    settings = bpy.context.scene.worldpaint
    bpy.ops.ed.undo_push(message="pasted")
    assert bpy.ops.worldpaint.pipette(location=(160.0, 70.0, 0.0), radius=40.0) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="WorldPaint Pipette")
    assert [c.name for c in settings.palette] == ["Forest", "Picked"]
    picked = engine.color_summary(settings.palette["Picked"].json)
    assert picked["region"] == {"shape": "circle", "center": [160.0, 70.0], "radius": 40.0}
    density = {c["name"]: c["density"] for c in picked["categories"]}["Tree"]
    assert abs(density / 0.04 - 1.0) <= 0.2, f"picked density {density:.4f}"
    assert bpy.data.images.get(settings.palette["Picked"].preview_image) is not None
    bpy.ops.ed.undo()
    assert [c.name for c in bpy.context.scene.worldpaint.palette] == ["Forest"]


def test_the_pipette_over_empty_ground_says_so_and_changes_nothing():
    forest()
    with pytest.raises(RuntimeError, match="Nothing to pick"):
        bpy.ops.worldpaint.pipette(location=(250.0, 30.0, 0.0), radius=10.0)
    assert len(bpy.context.scene.worldpaint.palette) == 1


def test_move_region_carries_the_content_and_keeps_its_count():
    forest()
    paste((60.0, 20.0), (140.0, 100.0))
    before = trees()
    bpy.ops.ed.undo_push(message="pasted")
    assert bpy.ops.worldpaint.move_region(region_mode='RECT', rect_min=(60.0, 20.0), rect_max=(140.0, 100.0),
                                          offset=(120.0, 10.0)) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="Move Region")
    after = trees()
    assert len(after) == len(before)
    assert (after[:, 0] >= 180.0).all() and (after[:, 0] <= 260.0).all()
    # on flat empty ground everything travels rigidly
    np.testing.assert_allclose(np.sort(after[:, 0]), np.sort(before[:, 0] + 120.0), atol=1e-3)
    bpy.ops.ed.undo()
    np.testing.assert_allclose(np.sort(trees()[:, 0]), np.sort(before[:, 0]))


def test_stretch_region_by_half_fills_the_new_space_with_the_color():
    tree = forest()
    paste((40.0, 20.0), (140.0, 80.0))
    before = trees()
    assert bpy.ops.worldpaint.stretch_region(region_mode='RECT', rect_min=(40.0, 20.0), rect_max=(140.0, 80.0),
                                             side='EAST', amount=50.0) == {'FINISHED'}
    after = trees()
    assert after[:, 0].max() > 180.0 and after[:, 0].max() <= 190.0
    ratio = len(after) / (150.0 * 60.0 * tree["density"])
    assert abs(ratio - 1.0) <= 0.12, f"stretched region holds {ratio:.2f} of the color's density"
    assert len(after) > len(before) * 1.3
    assert closest_pair(after[:, :2]) >= tree["min_distance"] - 1e-6
    with pytest.raises(RuntimeError, match="rectangle"):
        bpy.ops.worldpaint.stretch_region(region_mode='CIRCLE', circle_center=(90.0, 50.0), circle_radius=20.0)


def test_a_gradient_from_a_sparse_to_a_dense_color_rises_across_the_region():
    forest(density=0.01, name="Sparse", seed=5)
    examples = hard_core_examples("Tree", (200.0, 140.0), 60.0, 0.05, 2.0, 6)
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Dense", region_mode='RECT', rect_min=(200.0, 140.0),
                                          rect_max=(260.0, 200.0)) == {'FINISHED'}
    select_only([])
    bpy.context.scene.worldpaint.gradient_end = "Dense"
    assert bpy.ops.worldpaint.gradient(color="Sparse", region_mode='RECT', rect_min=(0.0, 0.0),
                                       rect_max=(300.0, 120.0), shape='LINEAR', toward='EAST') == {'FINISHED'}
    x = trees()[:, 0]
    bands = np.histogram(x, bins=5, range=(0.0, 300.0))[0] / (60.0 * 120.0)
    assert np.all(np.diff(bands) > 0), f"density across the gradient {np.round(bands, 4)}"


def test_a_gradient_runs_along_any_angle_and_a_bilinear_one_takes_four_corner_colors():
    prototypes()
    bpy.context.scene.worldpaint.terrain = flat_terrain(size=(520.0, 320.0))
    names = ("Sparse", "Light", "Medium", "Dense")
    for k, (name, density) in enumerate(zip(names, (0.008, 0.02, 0.035, 0.05), strict=True)):
        lo = (250.0 + 65.0 * (k % 4), 250.0)
        select_only(hard_core_examples("Tree", lo, 60.0, density, 2.0, 10 + k))
        assert bpy.ops.worldpaint.learn_color(name=name, region_mode='RECT', rect_min=lo,
                                              rect_max=(lo[0] + 60.0, lo[1] + 60.0)) == {'FINISHED'}
    select_only([])
    region = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (240.0, 240.0)}

    # toward the north-east (45°): sparse at the south-west corner, dense at the north-east one
    assert bpy.ops.worldpaint.gradient(color="Sparse", end_color="Dense", shape='LINEAR', toward='ANGLE',
                                       angle=np.pi / 4, **region) == {'FINISHED'}
    xy = trees()[:, :2]
    sw = np.sum((xy[:, 0] < 80.0) & (xy[:, 1] < 80.0)) / 6400.0
    ne = np.sum((xy[:, 0] > 160.0) & (xy[:, 1] > 160.0)) / 6400.0
    print(f"gradient toward 45°: south-west corner {sw:.4f}, north-east corner {ne:.4f} per m²")
    assert ne > 3.0 * sw, f"south-west {sw:.4f}, north-east {ne:.4f} per m²"

    # four corner colors: each corner's density is its color's
    with pytest.raises(RuntimeError, match="North-West and North-East"):
        bpy.ops.worldpaint.gradient(color="Sparse", end_color="Light", shape='BILINEAR', **region)
    assert bpy.ops.worldpaint.gradient(color="Sparse", end_color="Light", north_west_color="Medium",
                                       north_east_color="Dense", shape='BILINEAR', bands=3, **region) == {'FINISHED'}
    xy = trees()[:, :2]
    corners = {"Sparse": (0.0, 0.0), "Light": (160.0, 0.0), "Medium": (0.0, 160.0), "Dense": (160.0, 160.0)}
    palette = bpy.context.scene.worldpaint.palette
    for name, (x0, y0) in corners.items():
        inside = (xy[:, 0] >= x0) & (xy[:, 0] < x0 + 80.0) & (xy[:, 1] >= y0) & (xy[:, 1] < y0 + 80.0)
        density = inside.sum() / 6400.0
        want = engine.color_summary(palette[name].json)["categories"][0]["density"]
        print(f"bilinear gradient, {name}'s corner: {density:.4f} per m², its color {want:.4f}")
        assert abs(density / want - 1.0) < 0.25, f"{name}'s corner: {density:.4f} per m², its color {want:.4f}"


def test_blur_blends_the_edge_between_two_forests_inside_its_region_only():
    forest(density=0.05, name="Dense", seed=7)
    examples = hard_core_examples("Tree", (200.0, 140.0), 60.0, 0.008, 2.0, 8)
    select_only(examples)
    bpy.ops.worldpaint.learn_color(name="Sparse", region_mode='RECT', rect_min=(200.0, 140.0),
                                   rect_max=(260.0, 200.0))
    select_only([])
    paste((0.0, 0.0), (150.0, 130.0), color="Dense")
    paste((150.0, 0.0), (300.0, 130.0), color="Sparse")
    before = trees()
    blur = {"region_mode": 'RECT', "rect_min": (100.0, 20.0), "rect_max": (200.0, 110.0)}
    assert bpy.ops.worldpaint.blur(seed=3, **blur) == {'FINISHED'}
    after = trees()

    def outside(co):
        x, y = co[:, 0], co[:, 1]
        keep = ~((x >= 100.0) & (x <= 200.0) & (y >= 20.0) & (y <= 110.0))
        return np.sort(co[keep][:, 0])

    np.testing.assert_allclose(outside(after), outside(before))
    inside = after[(after[:, 1] >= 20.0) & (after[:, 1] <= 110.0)]
    bands = np.histogram(inside[:, 0], bins=4, range=(100.0, 200.0))[0] / (25.0 * 90.0)
    was = np.histogram(before[(before[:, 1] >= 20.0) & (before[:, 1] <= 110.0)][:, 0], bins=4,
                       range=(100.0, 200.0))[0] / (25.0 * 90.0)
    assert np.abs(np.diff(bands)).max() < 0.6 * np.abs(np.diff(was)).max(), f"{np.round(was, 4)} -> {bands}"


def test_palette_management_interpolate_duplicate_reorder_rename_export(tmp_path):
    forest(density=0.01, name="Sparse", seed=5)
    examples = hard_core_examples("Tree", (200.0, 140.0), 60.0, 0.05, 2.0, 6)
    select_only(examples)
    bpy.ops.worldpaint.learn_color(name="Dense", region_mode='RECT', rect_min=(200.0, 140.0),
                                   rect_max=(260.0, 200.0))
    settings = bpy.context.scene.worldpaint
    assert bpy.ops.worldpaint.interpolate_colors(color_a="Sparse", color_b="Dense", factor=0.5,
                                                 name="Between") == {'FINISHED'}
    density = {n: engine.color_summary(settings.palette[n].json)["categories"][0]["density"]
               for n in ("Sparse", "Dense", "Between")}
    assert density["Sparse"] < density["Between"] < density["Dense"]
    assert abs(density["Between"] - 0.5 * (density["Sparse"] + density["Dense"])) < 1e-9
    preview = engine.color_summary(settings.palette["Between"].json)["preview"]
    assert len(preview) > 0, "the interpolated color's preview shows an arrangement painted with it"

    settings.active_color_index = 0
    assert bpy.ops.worldpaint.duplicate_color() == {'FINISHED'}
    assert [c.name for c in settings.palette] == ["Sparse", "Dense", "Between", "Sparse 2"]
    assert bpy.ops.worldpaint.move_color(direction='UP') == {'FINISHED'}
    assert [c.name for c in settings.palette] == ["Sparse", "Dense", "Sparse 2", "Between"]
    settings.palette["Sparse 2"].name = "Meadow"
    path = tmp_path / "palette.json"
    assert bpy.ops.worldpaint.export_palette(filepath=str(path)) == {'FINISHED'}
    assert [c["name"] for c in json.loads(path.read_text())["colors"]] == ["Sparse", "Dense", "Meadow", "Between"]
    settings.active_color_index = 2
    assert bpy.ops.worldpaint.remove_color() == {'FINISHED'}
    assert [c.name for c in settings.palette] == ["Sparse", "Dense", "Between"]


def test_painting_operators_are_undoable_and_the_tools_are_in_the_toolbar():
    for op in ("brush", "erase", "pipette", "move_region", "stretch_region", "interpolate_colors", "gradient",
               "blur", "duplicate_color", "move_color", "remove_color"):
        assert 'UNDO' in getattr(bpy.types, f"WORLDPAINT_OT_{op}").bl_options, op
    from bl_ui.space_toolsystem_common import ToolSelectPanelHelper

    toolbar = ToolSelectPanelHelper._tool_class_from_space_type('VIEW_3D')
    ids = {t.idname for t in ToolSelectPanelHelper._tools_flatten(toolbar._tools['OBJECT']) if t is not None}
    assert {"worldpaint.brush_tool", "worldpaint.eraser_tool", "worldpaint.pipette_tool"} <= ids


def test_a_stroke_without_points_or_color_is_refused_and_changes_nothing():
    forest()
    paste((60.0, 20.0), (140.0, 100.0))
    n = len(trees())
    with pytest.raises(RuntimeError, match="no points"):
        bpy.ops.worldpaint.brush(stroke=[])
    with pytest.raises(RuntimeError, match="No color named"):
        bpy.ops.worldpaint.brush(stroke=stroke([(10.0, 10.0)]), color="Nope")
    assert len(trees()) == n


def test_stroke_worker_runs_points_in_order_and_drops_them_when_cancelled():
    import threading

    from worldpaint.ops.background import LatestWorker, QueueWorker

    seen, gate = [], threading.Event()
    worker = QueueWorker(lambda item: (gate.wait(), seen.append(item)))
    for k in range(5):
        worker.put(k)
    gate.set()
    worker.close()
    assert seen == [0, 1, 2, 3, 4]

    seen.clear()
    gate.clear()
    worker = QueueWorker(lambda item: (gate.wait(), seen.append(item)))
    for k in range(5):
        worker.put(k)
    threading.Timer(0.05, gate.set).start()
    worker.abort()
    assert len(seen) <= 1, "a cancelled stroke stops after the dab in progress"

    # a drag asks faster than the engine answers: only the newest position is computed last
    latest = LatestWorker(lambda offset: offset * 2)
    for k in range(100):
        latest.request(k)
    while not latest.idle():
        pass
    taken = latest.take()
    latest.close()
    assert taken == (99, 198)


def test_the_brush_finds_the_terrain_under_a_ray_on_a_moved_terrain():
    from mathutils import Vector
    from worldpaint.bridge.view import ground_circle, ray_to_terrain

    terrain_obj = flat_terrain(size=(100.0, 100.0))
    terrain_obj.location = (1000.0, 0.0, 25.0)
    terrain_obj.rotation_euler = (0.0, 0.0, 0.3)
    bpy.context.view_layer.update()
    hit = ray_to_terrain(terrain_obj, Vector((1020.0, 40.0, 500.0)), Vector((0.0, 0.0, -1.0)))
    assert hit is not None and abs(hit.z - 25.0) < 1e-4 and abs(hit.x - 1020.0) < 1e-4
    assert ray_to_terrain(terrain_obj, Vector((0.0, 0.0, 500.0)), Vector((0.0, 0.0, -1.0))) is None
    circle = ground_circle(terrain_obj, hit, 10.0)
    assert len(circle) > 8 and all(abs(p.z - 25.0) < 1e-4 for p in circle)
