"""Apply Sketch (thesis ch. 5) through bpy.ops, as an artist would use it: strokes drawn over a camera's view of a
hilly terrain become its silhouettes seen from that camera (checked by casting rays through the image columns on the
deformed mesh), the change is one shape key that undo removes, what stands on the ground moves with it, and a save
and reload keeps the result."""

import json
import math
import pathlib

import bpy
import numpy as np
import pytest
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector
from scene_kit import (
    SKETCH_CELL,
    draw_strokes,
    evaluated_vertices,
    hills_height,
    prototypes,
    sketch_scene,
    three_strokes,
)

KEY = "WorldPaint Apply Sketch"
TOLERANCE = 0.01  # of the image height: how far a stroke's silhouette may lie from it


def ray(camera, x, y):
    """The world ray (origin, unit direction) through camera-frame point (x, y)."""
    frame = camera.data.view_frame(scene=bpy.context.scene)
    xs, ys = [v.x for v in frame], [v.y for v in frame]
    local = Vector((min(xs) + x * (max(xs) - min(xs)), min(ys) + y * (max(ys) - min(ys)), frame[0].z))
    rotation = camera.matrix_world.to_3x3().normalized()
    return camera.matrix_world.translation.copy(), (rotation @ local).normalized()


def hit_depth(terrain, camera, x, y):
    """Depth (along the camera's view axis) where the ray through (x, y) meets the shown terrain, or None."""
    origin, direction = ray(camera, x, y)
    evaluated = terrain.evaluated_get(bpy.context.evaluated_depsgraph_get())
    inverse = terrain.matrix_world.inverted()
    hit, location, _, _ = evaluated.ray_cast(inverse @ origin, inverse.to_3x3() @ direction)
    if not hit:
        return None
    forward = camera.matrix_world.to_3x3().normalized() @ Vector((0.0, 0.0, -1.0))
    return (terrain.matrix_world @ location - origin).dot(forward)


def curve_depths(obj, camera):
    """(x, depth) of a curve's points in the camera frame, sorted by x."""
    scene = bpy.context.scene
    points = [obj.matrix_world @ Vector(p.co[:3]) for s in obj.data.splines for p in s.points]
    xd = np.array([tuple(world_to_camera_view(scene, camera, p))[::2] for p in points])
    return xd[np.argsort(xd[:, 0])]


def misplaced(terrain, camera, stroke, curve, margin=3.0 * SKETCH_CELL):
    """Columns of the stroke where the shown terrain's silhouette is not within TOLERANCE of it: a ray that far
    above meets the terrain before passing the stroke's curve, or a ray that far below passes it."""
    xd = curve_depths(curve, camera)
    bad, xs = 0, np.linspace(stroke[0, 0], stroke[-1, 0], 80)[1:-1]
    for x in xs:
        y = np.interp(x, stroke[:, 0], stroke[:, 1])
        depth = np.interp(x, xd[:, 0], xd[:, 1])
        above = hit_depth(terrain, camera, x, y + TOLERANCE)
        below = hit_depth(terrain, camera, x, y - TOLERANCE)
        if not ((above is None or above > depth + margin) and below is not None and below < depth + margin):
            bad += 1
    return bad, len(xs)


def test_sketched_silhouettes_are_seen_from_the_camera_and_the_far_terrain_stays():
    terrain, camera = sketch_scene()
    before = evaluated_vertices(terrain)
    strokes = three_strokes()
    draw_strokes(strokes)
    settings = bpy.context.scene.worldpaint.sketch
    settings.reach = 150.0
    OUT.mkdir(exist_ok=True)
    render(camera, OUT / "test_sketch_before.png")
    assert bpy.ops.worldpaint.apply_sketch() == {'FINISHED'}
    render(camera, OUT / "test_sketch_after.png")
    assert KEY in terrain.data.shape_keys.key_blocks
    ranks = [s.depth_rank for s in settings.strokes]
    print(f"depth ranks {ranks}")
    assert ranks[0] == 0, "the mountain the others disappear behind is in front"
    sketch = bpy.data.collections["Sketch"]
    curves = sorted((o for o in sketch.objects if o.get("wp_sketch") == "matched"), key=lambda o: o.name)
    assert len(curves) == 3
    for k, (stroke, curve) in enumerate(zip(strokes, curves, strict=True)):
        bad, columns = misplaced(terrain, camera, stroke, curve)
        print(f"stroke {k} ({curve.name}): {bad} of {columns} columns off by more than {TOLERANCE:.0%}")
        assert bad == 0
    after = evaluated_vertices(terrain)
    anchors = np.vstack([np.array([tuple(p.co[:2]) for s in o.data.splines for p in s.points])
                         for o in sketch.objects if o.get("wp_sketch") in ("matched", "lowered")])
    far = np.array([np.min(np.hypot(*(anchors - v[:2]).T)) > settings.reach + SKETCH_CELL for v in before])
    moved = np.abs(after[:, 2] - before[:, 2])
    print(f"{far.sum()} vertices beyond the reach, moved at most {moved[far].max():.2e} m; "
          f"largest change {moved.max():.1f} m")
    assert far.sum() > 1000 and moved[far].max() < 1e-4


def test_headless_strokes_undo_reseat_and_reload(tmp_path):
    from worldpaint.bridge import points
    from worldpaint.bridge.instances import point_cloud_arrays

    terrain, camera = sketch_scene()
    prototypes()
    xy = np.array([[256.0, 262.0], [150.0, 258.0], [300.0, 250.0], [40.0, 480.0]])
    cloud = points.point_cloud_object(bpy.context.scene, "Tree")
    points.write_points(cloud, np.column_stack([xy, hills_height(xy[:, 0], xy[:, 1])]), np.zeros(4), np.ones(4),
                        np.zeros(4, dtype=np.int32))
    bpy.ops.ed.undo_push(message="scene built")
    strokes = three_strokes()
    assert bpy.ops.worldpaint.apply_sketch(terrain="Terrain", camera="Camera",
                                           strokes=json.dumps([s.tolist() for s in strokes])) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="Apply Sketch")
    shown = evaluated_vertices(terrain)
    change = shown[:, 2] - hills_height(shown[:, 0], shown[:, 1])
    print(f"terrain change up to {np.abs(change).max():.1f} m")
    assert np.abs(change).max() > 5.0
    # the painted trees stand on the changed ground (within what the mesh's triangles and the engine's bilinear grid
    # disagree by on a raised crest)
    co = point_cloud_arrays(cloud)[0]
    ground = np.array([_ground(terrain, p) for p in co[:, :2]])
    rise = ground - hills_height(xy[:, 0], xy[:, 1])
    print(f"trees at {co[:, 2].round(2)}, ground {ground.round(2)}, the ground rose by {rise.round(2)}")
    assert rise.max() > 10.0, "a tree stands on a raised crest"
    assert np.abs(co[:, 2] - ground).max() < 0.5, "the trees moved with the ground"
    bpy.ops.ed.undo()
    terrain = bpy.data.objects["Terrain"]
    assert terrain.data.shape_keys is None or KEY not in terrain.data.shape_keys.key_blocks, "undo removes it"
    bpy.ops.ed.redo()
    terrain = bpy.data.objects["Terrain"]
    assert np.abs(evaluated_vertices(terrain) - shown).max() < 1e-4, "redo brings it back"
    path = str(tmp_path / "sketch.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    reloaded = evaluated_vertices(bpy.data.objects["Terrain"])
    assert np.abs(reloaded - shown).max() < 1e-4, "the sketch survives save and reload"
    assert bpy.data.objects["Terrain"].data.shape_keys.key_blocks[KEY].value == 1.0


def test_a_sketch_in_another_scene_leaves_this_scenes_trees_where_they_stand():
    """Two scenes over the same ground: the trees painted in the first stay out of the second and do not move when
    Apply Sketch deforms the second's terrain under them."""
    from worldpaint.bridge import points
    from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

    first = bpy.context.scene
    sketch_scene()
    prototypes()
    xy = np.array([[256.0, 262.0], [150.0, 258.0], [300.0, 250.0]])
    cloud = points.point_cloud_object(first, "Tree")
    points.write_points(cloud, np.column_stack([xy, hills_height(xy[:, 0], xy[:, 1])]), np.zeros(3), np.ones(3),
                        np.zeros(3, dtype=np.int32))
    before = point_cloud_arrays(cloud)[0].copy()
    second = bpy.data.scenes.new("Second")
    with bpy.context.temp_override(scene=second, view_layer=second.view_layers[0]):
        terrain, camera = sketch_scene("Second hills", "Second camera")
        assert point_cloud_objects(second) == {}, "the first scene's trees are not in the second"
        assert bpy.ops.worldpaint.apply_sketch(terrain=terrain.name, camera=camera.name, strokes=json.dumps(
            [s.tolist() for s in three_strokes()])) == {'FINISHED'}
        shown = evaluated_vertices(terrain)
        rise = shown[:, 2] - hills_height(shown[:, 0], shown[:, 1])
        own = points.worldpaint_collection(second, create=False)
    print(f"the second terrain rose by up to {rise.max():.1f} m; the first scene's trees moved by "
          f"{np.abs(point_cloud_arrays(cloud)[0] - before).max():.2e} m")
    assert rise.max() > 10.0
    assert np.array_equal(point_cloud_arrays(cloud)[0], before)
    assert own is not None and own != points.worldpaint_collection(first, create=False)
    assert own.name not in first.collection.children and cloud.name not in second.objects


def _ground(terrain, xy):
    """Height of the shown terrain at XY, by a vertical ray."""
    evaluated = terrain.evaluated_get(bpy.context.evaluated_depsgraph_get())
    inverse = terrain.matrix_world.inverted()
    hit, location, _, _ = evaluated.ray_cast(inverse @ Vector((xy[0], xy[1], 1000.0)), Vector((0.0, 0.0, -1.0)))
    assert hit
    return (terrain.matrix_world @ location).z


def test_bad_sketches_are_refused_and_the_terrain_is_left_as_it_was():
    terrain, _ = sketch_scene()
    with pytest.raises(RuntimeError, match="Nothing to apply"):
        bpy.ops.worldpaint.apply_sketch()
    with pytest.raises(RuntimeError, match="JSON"):
        bpy.ops.worldpaint.apply_sketch(strokes="[[0.1, 0.5], oops]")
    with pytest.raises(RuntimeError, match="fewer than two points"):
        bpy.ops.worldpaint.apply_sketch(strokes="[[[0.1, 0.5]]]")
    with pytest.raises(RuntimeError, match="not finite|NaN|nan"):
        bpy.ops.worldpaint.apply_sketch(strokes="[[[0.1, 0.5], [NaN, 0.6]]]")
    bpy.context.scene.camera = None
    with pytest.raises(RuntimeError, match="No camera"):
        bpy.ops.worldpaint.apply_sketch(strokes="[[[0.1, 0.5], [0.3, 0.6]]]")
    assert terrain.data.shape_keys is None


REAL = pathlib.Path(__file__).resolve().parents[2] / "shared" / "data" / "real" / "terrain" / "andorra_srtm3.asc"
OUT = pathlib.Path(__file__).resolve().parents[1] / "out"


def srtm_window(path, row0, col0, size, upsample=1):
    """A size × size window of an ESRI ASCII SRTM grid as world XYZ (metres, equirectangular about its centre;
    the grid's first row is its northern edge) and quads, ``upsample`` times finer (bilinear), as an artist
    subdivides a heightmap before shaping it."""
    with open(path) as f:
        header = dict(next(f).split() for _ in range(6))
        grid = np.loadtxt(f, dtype=np.float64)
    cell = float(header["cellsize"])
    lat = float(header["yllcorner"]) + cell * (grid.shape[0] - row0 - size / 2)
    heights = grid[row0:row0 + size, col0:col0 + size][::-1]  # south to north
    assert (heights > -1000).all(), "no missing samples in the window"
    fine = np.linspace(0.0, size - 1.0, (size - 1) * upsample + 1)
    heights = np.array([np.interp(fine, np.arange(size), row) for row in heights])
    heights = np.array([np.interp(fine, np.arange(size), col) for col in heights.T]).T
    size = len(fine)
    dx, dy = (cell * 111_320.0 * math.cos(math.radians(lat)) / upsample, cell * 111_320.0 / upsample)
    x, y = np.meshgrid(dx * np.arange(size), dy * np.arange(size))
    i, j = np.meshgrid(np.arange(size - 1), np.arange(size - 1))
    v0 = (j * size + i).ravel()
    quads = np.column_stack([v0, v0 + 1, v0 + 1 + size, v0 + size])
    return np.column_stack([x.ravel(), y.ravel(), heights.ravel()]), quads, (dx, dy)


def render(camera, path):
    """A Workbench picture from the camera, under a pale sky."""
    scene = bpy.context.scene
    if scene.world is None:
        scene.world = bpy.data.worlds.new("Sky")
        scene.world.color = (0.62, 0.74, 0.88)
    scene.render.engine = 'BLENDER_WORKBENCH'
    scene.display.shading.light = 'STUDIO'
    scene.display.shading.color_type = 'OBJECT'
    scene.render.resolution_percentage = 50
    scene.render.filepath = str(path)
    scene.camera = camera
    bpy.ops.render.render(write_still=True)


@pytest.mark.skipif(not REAL.exists(), reason="the real terrains live beside the project, in shared/data/real")
@pytest.mark.parametrize("view", [
    "peak",
    pytest.param("tile edge", marks=pytest.mark.xfail(
        strict=True, reason="open (issue 18): the ridge in front is raised 550 m to reach the stroke and about a "
                            "quarter of the columns stay more than 1 % off, at the stroke's ends and where the "
                            "raised ground behind it still shows")),
])
def test_a_silhouette_taller_than_a_real_ridge_is_met_on_real_terrain(view):
    """Two views of Andorra: 2.5 km south of the window's highest inner peak, whose ridge is the skyline; and from
    the lowest ground of the window's southern middle looking north, where the skyline is partly the window's far
    edge (a DEM tile seen across), so the stroke must be served by the ridges in front of it."""
    from scene_kit import mesh_object

    co, quads, (dx, dy) = srtm_window(REAL, 100, 180, 64, upsample=3)
    terrain = mesh_object("Andorra", co, quads)
    terrain.color = (0.55, 0.5, 0.38, 1.0)
    scene = bpy.context.scene
    scene.worldpaint.terrain = terrain
    scene.render.resolution_x, scene.render.resolution_y = 1200, 800
    width, depth = np.ptp(co[:, 0]), np.ptp(co[:, 1])
    if view == "peak":
        inner = co[(np.abs(co[:, 0] - 0.5 * width) < 0.2 * width) & (co[:, 1] > 0.45 * depth)
                   & (co[:, 1] < 0.8 * depth)]
        peak = inner[np.argmax(inner[:, 2])]
        eye = peak[:2] - (0.0, 2500.0)
        pitch = math.atan2(peak[2] - co[np.argmin(np.hypot(*(co[:, :2] - eye).T)), 2] - 30.0, 2500.0)
    else:
        south = co[(co[:, 1] < 6 * dy) & (np.abs(co[:, 0] - 0.5 * width) < 0.2 * width)]
        eye, pitch = south[np.argmin(south[:, 2]), :2], math.radians(2.0)
    # off the grid's lines: a ray running exactly along a mesh edge may slip between its faces
    eye = eye + (0.37 * dx, 0.41 * dy)
    ground = co[np.argmin(np.hypot(co[:, 0] - eye[0], co[:, 1] - eye[1])), 2]
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.sensor_fit = 'HORIZONTAL'
    camera.data.angle = math.radians(60.0)
    camera.data.clip_end = 20_000.0
    camera.location = (eye[0], eye[1], ground + 30.0)
    camera.rotation_euler = (math.radians(85.0) + pitch, 0.0, 0.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    bpy.context.view_layer.update()
    OUT.mkdir(exist_ok=True)
    name = view.replace(" ", "_")
    render(camera, OUT / f"sketch_real_{name}_before.png")
    # the real skyline in the middle of the view, by rays through the columns, and a stroke well above it
    xs = np.linspace(0.35, 0.65, 31)
    skyline = np.array([_column_top(terrain, camera, x) for x in xs])
    stroke = np.column_stack([xs, skyline + 0.02 + 0.03 * np.sin(np.pi * (xs - 0.35) / 0.3)])
    assert bpy.ops.worldpaint.apply_sketch(strokes=json.dumps([stroke.tolist()])) == {'FINISHED'}
    render(camera, OUT / f"sketch_real_{name}_after.png")
    curve = next(o for o in bpy.data.collections["Sketch"].objects if o.get("wp_sketch") == "matched")
    bad, columns = misplaced(terrain, camera, stroke, curve, margin=3.0 * max(dx, dy))
    raised = _column_top(terrain, camera, 0.5) - skyline[15]
    print(f"{view}: real terrain {np.ptp(co[:, 0]):.0f} × {np.ptp(co[:, 1]):.0f} m, relief {np.ptp(co[:, 2]):.0f} m; "
          f"skyline raised by {raised:.3f} of the image height at the centre; {bad} of {columns} columns off by "
          f"more than {TOLERANCE:.0%}; renders in {OUT}")
    assert bad == 0


def _column_top(terrain, camera, x):
    """The image y of the shown terrain's silhouette in column x (the highest ray that meets it)."""
    lo, hi = 0.0, 1.0
    assert hit_depth(terrain, camera, x, lo) is not None and hit_depth(terrain, camera, x, hi) is None
    for _ in range(20):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if hit_depth(terrain, camera, x, mid) is not None else (lo, mid)
    return lo
