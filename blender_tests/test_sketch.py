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


def test_the_frame_aspect_reach_and_completion_reach_the_engine():
    """On a 1920 × 800 render (pixel aspect 1.2 : 1.0, sensor fit vertical: a frame 2.88 times wider than tall), a
    stroke that comes down to 0.03 image heights above another ends on it (0.0104 frame widths, within the junction
    distance): it is behind it. Read as a square frame it would be 0.03 away, no junction, and the cue of the lower
    stroke's wider projection would put it in front. Reach and completion given to the operator override the panel's."""
    from worldpaint.bridge import sketch as sketch_bridge

    terrain, camera = sketch_scene()
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 1920, 800
    scene.render.pixel_aspect_x, scene.render.pixel_aspect_y = 1.2, 1.0
    camera.data.sensor_fit = 'VERTICAL'
    frame = camera.data.view_frame(scene=scene)
    width, height = (np.ptp([v.x for v in frame]), np.ptp([v.y for v in frame]))
    assert abs(sketch_bridge.frame_aspect(scene) - width / height) < 1e-6
    assert abs(width / height - 2.88) < 1e-6
    front = np.column_stack([np.linspace(0.1, 0.9, 40), np.full(40, 0.62)])
    ending = np.column_stack([np.linspace(0.2, 0.5, 20), np.linspace(0.85, 0.65, 20)])
    draw_strokes([front, ending])
    settings = scene.worldpaint.sketch
    settings.reach, settings.completion = 150.0, True
    before = evaluated_vertices(terrain)
    assert bpy.ops.worldpaint.apply_sketch(reach=40.0, completion=False) == {'FINISHED'}
    ranks = [s.depth_rank for s in settings.strokes]
    sketch = bpy.data.collections["Sketch"]
    curves = [o for o in sketch.objects if o.get("wp_sketch") in ("matched", "lowered")]
    anchors = np.vstack([np.array([tuple(p.co[:2]) for s in o.data.splines for p in s.points]) for o in curves])
    moved = np.abs(evaluated_vertices(terrain)[:, 2] - before[:, 2]) > 1e-4
    farthest = max(np.min(np.hypot(*(anchors - v[:2]).T)) for v in before[moved])
    print(f"frame aspect {width / height:.2f}: depth ranks {ranks}; {moved.sum()} vertices moved, the farthest "
          f"{farthest:.1f} m from the curves (reach 40 m given, 150 m on the panel)")
    assert ranks == [0, 1], "the stroke ending on the other is behind it"
    assert farthest < 40.0 + 2.0 * SKETCH_CELL
    assert settings.reach == 150.0 and settings.completion, "the panel's settings stay as they were"


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


def srtm_window(path, row0, col0, size, upsample=1, cols=None):
    """A window of an ESRI ASCII SRTM grid, ``size`` rows by ``cols`` columns (``size`` too by default), as world XYZ
    (metres, equirectangular about its centre; the grid's first row is its northern edge) and quads, ``upsample``
    times finer (bilinear), as an artist subdivides a heightmap before shaping it."""
    cols = cols or size
    with open(path) as f:
        header = dict(next(f).split() for _ in range(6))
        grid = np.loadtxt(f, dtype=np.float64)
    cell = float(header["cellsize"])
    lat = float(header["yllcorner"]) + cell * (grid.shape[0] - row0 - size / 2)
    heights = grid[row0:row0 + size, col0:col0 + cols][::-1]  # south to north
    assert (heights > -1000).all(), "no missing samples in the window"
    fine_x = np.linspace(0.0, cols - 1.0, (cols - 1) * upsample + 1)
    fine_y = np.linspace(0.0, size - 1.0, (size - 1) * upsample + 1)
    heights = np.array([np.interp(fine_x, np.arange(cols), row) for row in heights])
    heights = np.array([np.interp(fine_y, np.arange(size), col) for col in heights.T]).T
    ny, nx = heights.shape
    dx, dy = (cell * 111_320.0 * math.cos(math.radians(lat)) / upsample, cell * 111_320.0 / upsample)
    x, y = np.meshgrid(dx * np.arange(nx), dy * np.arange(ny))
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1))
    v0 = (j * nx + i).ravel()
    quads = np.column_stack([v0, v0 + 1, v0 + 1 + nx, v0 + nx])
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
        strict=True, reason="open (issue 18): where the skyline is the window's own far edge no silhouette is seen "
                            "there, the skyline taken under the stroke is the ground below it, raised up to 500 m, "
                            "and 3 of 78 columns stay more than 1 % off (21 before the stroke could take the "
                            "skyline)")),
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


def _seen_at(camera, x, y, p):
    """The height at which the ray through (x, y) passes above p's ground position (at p's horizontal distance)."""
    origin, direction = ray(camera, x, y)
    t = math.hypot(p[0] - origin.x, p[1] - origin.y) / math.hypot(direction.x, direction.y)
    return origin.z + direction.z * t


def _skyline_point(terrain, camera, x, y):
    """The point of the shown terrain the ray through (x, y) grazes (y its column's skyline)."""
    origin, direction = ray(camera, x, y)
    evaluated = terrain.evaluated_get(bpy.context.evaluated_depsgraph_get())
    inverse = terrain.matrix_world.inverted()
    hit, location, _, _ = evaluated.ray_cast(inverse @ origin, inverse.to_3x3() @ direction)
    assert hit
    return terrain.matrix_world @ location


@pytest.mark.skipif(not REAL.exists(), reason="the real terrains live beside the project, in shared/data/real")
@pytest.mark.parametrize("view, window, eye, heading, pitch", [
    ("north", (80, 320), (0.5, 0.3), 0.0, 5.7),
    ("north-west", (140, 280), (0.5, 0.2), 45.0, 4.5),
])
def test_strokes_just_above_a_real_skyline_lift_its_own_ridges(view, window, eye, heading, pitch):
    """A 3.6 × 3.7 km window of the Pyrenees around Andorra (about 800 m of relief), seen from 10 m above the ground
    with the skyline 1.1-1.8 km away: a peak over the right of the view and a ridge over the left that comes down
    onto the peak's slope behind it (its end on the peak, the peak's foot 2.4 % of the image below the ridge: within
    the T-junction distance), each 3.5-7 % of the image height above the present skyline. The skyline becomes the
    strokes in at least 95 % of their columns (within 1.5 % of the image height), the peak stays in front, and no
    ground rises more than 1.25 times what lifting the present skyline's own points to the strokes would need (found
    by casting a ray through each column)."""
    from scene_kit import mesh_object

    co, quads, (dx, dy) = srtm_window(REAL, *window, 41, upsample=3, cols=54)
    terrain = mesh_object("Andorra", co, quads)
    terrain.color = (0.55, 0.5, 0.38, 1.0)
    scene = bpy.context.scene
    scene.worldpaint.terrain = terrain
    scene.render.resolution_x, scene.render.resolution_y = 1200, 800
    eye = np.array(eye) * np.ptp(co[:, :2], axis=0) + (0.37 * dx, 0.41 * dy)
    ground = co[np.argmin(np.hypot(co[:, 0] - eye[0], co[:, 1] - eye[1])), 2]
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.sensor_fit = 'HORIZONTAL'
    camera.data.angle = math.radians(60.0)
    camera.data.clip_end = 20_000.0
    camera.location = (eye[0], eye[1], ground + 10.0)
    camera.rotation_euler = (math.radians(90.0 + pitch), 0.0, math.radians(heading))
    scene.collection.objects.link(camera)
    scene.camera = camera
    bpy.context.view_layer.update()
    OUT.mkdir(exist_ok=True)
    name = view.replace("-", "_")
    render(camera, OUT / f"sketch_skyline_{name}_before.png")
    xs = np.linspace(0.05, 0.95, 91)
    skyline = np.array([_column_top(terrain, camera, x) for x in xs])
    points = [_skyline_point(terrain, camera, x, y) for x, y in zip(xs, skyline, strict=True)]
    distance = np.array([math.hypot(p.x - eye[0], p.y - eye[1]) for p in points])

    def above_skyline(corners):
        corners = np.array(corners)
        inside = (xs >= corners[0, 0]) & (xs <= corners[-1, 0])
        return np.column_stack([xs[inside], skyline[inside] + np.interp(xs[inside], *corners.T)])

    peak = above_skyline([(0.47, 0.035), (0.7, 0.07), (0.92, 0.035)])
    ridge = above_skyline([(0.08, 0.035), (0.3, 0.07), (0.55, 0.05)])
    ridge[-1, 1] = np.interp(ridge[-1, 0], *peak.T)  # the ridge ends on the peak's slope
    draw_strokes([peak, ridge])
    before = evaluated_vertices(terrain)
    assert bpy.ops.worldpaint.apply_sketch() == {'FINISHED'}
    render(camera, OUT / f"sketch_skyline_{name}_after.png")
    ranks = [s.depth_rank for s in scene.worldpaint.sketch.strokes]
    rise = evaluated_vertices(terrain)[:, 2] - before[:, 2]
    # each column's highest stroke: what its skyline should now be, and what lifting its old skyline there needs
    top = np.full(len(xs), np.nan)
    for stroke in (peak, ridge):
        inside = (xs >= stroke[0, 0]) & (xs <= stroke[-1, 0])
        top[inside] = np.fmax(top[inside], np.interp(xs[inside], *stroke.T))
    drawn = ~np.isnan(top)
    needed = max(_seen_at(camera, x, y, p) - p.z for x, y, p, d in zip(xs, top, points, drawn, strict=True) if d)
    shown = np.array([_column_top(terrain, camera, x) for x in xs[drawn]])
    met = np.abs(shown - top[drawn]) <= 0.015
    k = int(np.argmax(rise))
    print(f"{view}: real terrain {np.ptp(co[:, 0]):.0f} × {np.ptp(co[:, 1]):.0f} m, relief {np.ptp(co[:, 2]):.0f} m, "
          f"skyline {distance.min():.0f}-{distance.max():.0f} m away; depth ranks {ranks}; {met.sum()} of {len(met)} "
          f"columns within 1.5 %; largest rise {rise.max():.1f} m, {math.hypot(*(co[k, :2] - eye)):.0f} m from the "
          f"camera; lifting the skyline needs {needed:.1f} m (ratio {rise.max() / needed:.2f}); renders in {OUT}")
    assert ranks == [0, 1], "the peak the ridge ends on is in front"
    assert met.mean() >= 0.95
    assert rise.max() <= 1.25 * needed
