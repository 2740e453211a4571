"""Silhouettes sketched over a camera's view (thesis ch. 5): a pixel of a viewport looking through the camera is read
where the camera frame shows it whatever the view's zoom, pan and the camera's lens shift; annotation strokes are
read through the camera; the drawn strokes can be removed one by one or cleared, are saved in the .blend, and bad
input (no camera, an orthographic one, no strokes) is reported with what to do."""

import math

import bpy
import numpy as np
import pytest
from bpy_extras import view3d_utils
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Matrix, Vector
from worldpaint.bridge import WorldPaintError
from worldpaint.bridge.sketch_strokes import (
    NOTHING_TO_APPLY,
    annotation_data,
    camera_to_region,
    camera_to_world,
    look_through,
    looks_through,
    region_to_camera,
    sketch_camera,
    sketch_strokes,
)
from worldpaint.ops.sketch_draw import UNRANKED_COLOR, draw_overlay, rank_color


def add_camera(name="Sketch Camera", shift=(0.0, 0.0), lens=35.0, kind='PERSP', make_scene_camera=True):
    data = bpy.data.cameras.new(name)
    data.type = kind
    data.lens = lens
    data.shift_x, data.shift_y = shift
    obj = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(obj)
    # standing 50 m south of the origin, 12 m up, looking north and a little down
    obj.location = (3.0, -50.0, 12.0)
    obj.rotation_euler = (math.radians(78.0), 0.0, math.radians(4.0))
    if make_scene_camera:
        bpy.context.scene.camera = obj
    bpy.context.view_layer.update()
    return obj


def set_resolution(x, y):
    bpy.context.scene.render.resolution_x = x
    bpy.context.scene.render.resolution_y = y
    bpy.context.scene.render.resolution_percentage = 100


class Region:
    """A 3D viewport region's size, as ``bpy_extras.view3d_utils`` reads it."""

    def __init__(self, width, height):
        self.width, self.height = width, height


class CameraView:
    """What a 3D viewport's ``RegionView3D`` holds when it looks through ``camera``: the camera's view matrix, and a
    projection that shows the camera frame on the region's pixel rectangle ``frame_px`` (x0, y0, x1, y1): the camera
    view zoomed and panned. (Blender as a module draws no viewport, so its own view matrices are never computed.)"""

    is_perspective = True
    view_perspective = 'CAMERA'

    def __init__(self, scene, camera, region, frame_px):
        depsgraph = bpy.context.evaluated_depsgraph_get()
        render = scene.render
        projection = camera.calc_matrix_camera(
            depsgraph, x=render.resolution_x, y=render.resolution_y,
            scale_x=render.pixel_aspect_x, scale_y=render.pixel_aspect_y,
        )
        x0, y0, x1, y1 = frame_px
        # the camera frame's normalized device coordinates [-1, 1] onto the region's [x0, x1] x [y0, y1]
        to_region = Matrix.Identity(4)
        to_region[0][0] = (x1 - x0) / region.width
        to_region[0][3] = (x0 + x1) / region.width - 1.0
        to_region[1][1] = (y1 - y0) / region.height
        to_region[1][3] = (y0 + y1) / region.height - 1.0
        self.view_matrix = camera.matrix_world.normalized().inverted()
        self.perspective_matrix = to_region @ projection @ self.view_matrix


FRAMES = {
    "fitted": (1200, 800, (100.0, 62.5, 1100.0, 737.5)),
    "zoomed in and panned": (900, 700, (-420.0, -160.0, 1480.0, 908.75)),
    "zoomed out, off-centre": (1600, 900, (900.0, 100.0, 1380.0, 370.0)),
}


@pytest.mark.parametrize("shift", [(0.0, 0.0), (0.25, -0.15)], ids=["centred lens", "shifted lens"])
@pytest.mark.parametrize("view", list(FRAMES), ids=list(FRAMES))
def test_a_pixel_of_the_camera_view_is_read_where_the_camera_frame_shows_it(view, shift):
    set_resolution(1920, 1080)
    camera = add_camera(shift=shift)
    scene = bpy.context.scene
    width, height, frame_px = FRAMES[view]
    region = Region(width, height)
    rv3d = CameraView(scene, camera, region, frame_px)
    x0, y0, x1, y1 = frame_px

    # the corners and the middle of the camera frame as the viewport shows it
    for u, v in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.5, 0.5), (0.3, 0.8)]:
        pixel = (x0 + u * (x1 - x0), y0 + v * (y1 - y0))
        co = region_to_camera(region, rv3d, scene, camera, pixel)
        assert co == pytest.approx((u, v), abs=1e-4), (pixel, co)
        back = camera_to_region(region, rv3d, scene, camera, co)
        assert back == pytest.approx(pixel, abs=0.05)  # float32 matrices: a twentieth of a pixel

    # a point of the world: the pixel showing it is read as the camera sees it
    for point in [Vector((0.0, 0.0, 0.0)), Vector((-20.0, 40.0, 25.0)), Vector((15.0, 10.0, -3.0))]:
        pixel = view3d_utils.location_3d_to_region_2d(region, rv3d, point)
        expected = world_to_camera_view(scene, camera, point)
        co = region_to_camera(region, rv3d, scene, camera, pixel)
        assert co == pytest.approx((expected.x, expected.y), abs=1e-4)


@pytest.mark.parametrize("resolution", [(1920, 1080), (800, 1200)], ids=["landscape", "portrait"])
def test_camera_frame_points_are_seen_by_the_camera_where_they_were_drawn(resolution):
    set_resolution(*resolution)
    camera = add_camera(shift=(-0.1, 0.2), lens=50.0)
    scene = bpy.context.scene
    for co in [(0.0, 0.0), (1.0, 1.0), (0.25, 0.75), (1.3, -0.2)]:
        for depth in (1.0, 80.0):
            point = camera_to_world(scene, camera, co, depth)
            seen = world_to_camera_view(scene, camera, point)
            assert (seen.x, seen.y, seen.z) == pytest.approx((*co, depth), abs=1e-5)


# --- the sketch camera --------------------------------------------------------------------------------------------

def test_the_sketch_camera_is_the_panel_camera_else_the_scene_camera():
    settings = bpy.context.scene.worldpaint.sketch
    scene_camera = add_camera("Scene Camera")
    assert sketch_camera(bpy.context, settings) == scene_camera
    other = add_camera("Viewpoint", make_scene_camera=False)
    settings.camera = other
    assert sketch_camera(bpy.context, settings) == other


def test_sketching_without_a_camera_says_where_to_pick_one():
    with pytest.raises(RuntimeError, match="No camera to sketch through"):
        bpy.ops.worldpaint.sketch_silhouettes(stroke=[{"name": "", "co": (0.1, 0.5)}, {"name": "", "co": (0.9, 0.6)}])
    assert len(bpy.context.scene.worldpaint.sketch.strokes) == 0


def test_an_orthographic_camera_is_refused_and_so_is_an_object_that_is_no_camera():
    settings = bpy.context.scene.worldpaint.sketch
    add_camera(kind='ORTHO')
    with pytest.raises(RuntimeError, match="orthographic: sketching needs a perspective camera"):
        bpy.ops.worldpaint.sketch_silhouettes(stroke=[{"name": "", "co": (0.1, 0.5)}, {"name": "", "co": (0.9, 0.6)}])
    mesh = bpy.data.objects.new("Rock", bpy.data.meshes.new("Rock"))
    bpy.context.scene.collection.objects.link(mesh)
    settings.camera = mesh
    with pytest.raises(WorldPaintError, match="'Rock' is not a camera"):
        sketch_camera(bpy.context, settings)
    assert len(settings.strokes) == 0


# --- drawn strokes ------------------------------------------------------------------------------------------------

RIDGE = [(0.05, 0.40), (0.30, 0.55), (0.55, 0.48), (0.95, 0.62)]
SPUR = [(0.20, 0.30), (0.42, 0.52)]  # ends on the ridge: a T-junction


def draw(points):
    return bpy.ops.worldpaint.sketch_silhouettes(stroke=[{"name": "", "co": co} for co in points])


def test_strokes_given_by_a_script_are_applied_in_the_order_drawn_and_a_one_point_stroke_is_refused():
    add_camera()
    assert draw(RIDGE) == {'FINISHED'}
    assert draw(SPUR) == {'FINISHED'}
    with pytest.raises(RuntimeError, match="at least 2 distinct points"):
        draw([(0.5, 0.5), (0.5, 0.5)])
    settings = bpy.context.scene.worldpaint.sketch
    assert len(settings.strokes) == 2 and all(s.depth_rank == -1 for s in settings.strokes)
    strokes = sketch_strokes(bpy.context, settings, sketch_camera(bpy.context, settings))
    assert [s.dtype for s in strokes] == [np.float64, np.float64]
    assert np.allclose(strokes[0], RIDGE) and np.allclose(strokes[1], SPUR)
    assert strokes.origins == [0, 1] and strokes.skipped == []


def test_a_stroke_of_one_point_left_in_the_scene_is_skipped_with_the_reason():
    add_camera()
    settings = bpy.context.scene.worldpaint.sketch
    draw(RIDGE)
    dot = settings.strokes.add()
    dot.points.add().co = (0.5, 0.5)
    draw(SPUR)
    strokes = sketch_strokes(bpy.context, settings, sketch_camera(bpy.context, settings))
    assert len(strokes) == 2 and strokes.origins == [0, 2]
    assert strokes.skipped == ["stroke 2 skipped: it has 1 distinct point(s), 2 needed"]


def test_nothing_to_apply_says_how_to_sketch():
    camera = add_camera()
    settings = bpy.context.scene.worldpaint.sketch
    with pytest.raises(WorldPaintError, match="Nothing to apply: draw silhouettes with the Sketch Silhouettes tool"):
        sketch_strokes(bpy.context, settings, camera)
    assert NOTHING_TO_APPLY.startswith("Nothing to apply")


def test_remove_last_and_clear_edit_the_sketch_and_are_refused_on_an_empty_one():
    add_camera()
    settings = bpy.context.scene.worldpaint.sketch
    for stroke in (RIDGE, SPUR, RIDGE[1:]):
        draw(stroke)
    assert bpy.ops.worldpaint.sketch_remove_last() == {'FINISHED'}
    assert len(settings.strokes) == 2
    assert np.allclose([tuple(p.co) for p in settings.strokes[-1].points], SPUR)
    assert bpy.ops.worldpaint.sketch_clear() == {'FINISHED'}
    assert len(settings.strokes) == 0
    for operator in (bpy.ops.worldpaint.sketch_remove_last, bpy.ops.worldpaint.sketch_clear):
        with pytest.raises(RuntimeError):
            operator()


def test_the_sketch_survives_save_and_reload(tmp_path):
    camera = add_camera("Viewpoint", make_scene_camera=False)
    add_camera("Scene Camera")
    settings = bpy.context.scene.worldpaint.sketch
    settings.camera = camera
    draw(RIDGE)
    draw(SPUR)
    settings.strokes[0].depth_rank = 1
    settings.strokes[1].depth_rank = 0
    settings.source = 'ANNOTATION'
    settings.annotation_layer = "Silhouettes"
    settings.reach = 350.0
    settings.completion = False
    path = str(tmp_path / "sketch.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=path)

    settings = bpy.context.scene.worldpaint.sketch
    assert settings.camera is not None and settings.camera.name == "Viewpoint"
    assert bpy.context.scene.camera.name == "Scene Camera"
    assert [s.depth_rank for s in settings.strokes] == [1, 0]
    assert np.allclose([tuple(p.co) for p in settings.strokes[0].points], RIDGE)
    assert np.allclose([tuple(p.co) for p in settings.strokes[1].points], SPUR)
    assert (settings.source, settings.annotation_layer) == ('ANNOTATION', "Silhouettes")
    assert settings.reach == pytest.approx(350.0) and not settings.completion


def test_depth_colors_run_from_blue_in_front_to_red_at_the_back_and_grey_before_apply():
    front, middle, back = (rank_color(r, 2) for r in range(3))
    assert front[2] > 0.9 and front[0] < 0.3, front  # blue
    assert back[0] > 0.9 and back[2] < 0.3, back  # red
    assert middle != front and middle != back
    assert rank_color(-1, 2) == UNRANKED_COLOR
    assert rank_color(0, 0)[2] > 0.9


def test_the_overlay_draws_nothing_without_a_viewport():
    add_camera()
    draw(RIDGE)
    draw_overlay()  # Blender as a module draws no viewport: the handler must simply return


# --- the viewport -------------------------------------------------------------------------------------------------

def view3d_area():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    return window, area, region


def test_a_viewport_is_switched_to_the_sketch_camera_and_the_scene_camera_is_left_alone():
    scene = bpy.context.scene
    scene_camera = add_camera("Scene Camera")
    viewpoint = add_camera("Viewpoint", make_scene_camera=False)
    _window, area, _region = view3d_area()
    space = area.spaces.active
    space.region_3d.view_perspective = 'PERSP'
    assert not looks_through(scene, space, space.region_3d, scene_camera)
    # what the tool's first click does when the viewport does not look through the sketch camera
    look_through(scene, space, scene_camera)
    assert looks_through(scene, space, space.region_3d, scene_camera)
    look_through(scene, space, viewpoint)
    assert space.region_3d.view_perspective == 'CAMERA'
    assert space.use_local_camera and space.camera == viewpoint
    assert looks_through(scene, space, space.region_3d, viewpoint)
    assert not looks_through(scene, space, space.region_3d, scene_camera)
    assert scene.camera == scene_camera


def test_sketching_outside_a_3d_viewport_says_where_to_draw():
    add_camera()
    with pytest.raises(RuntimeError, match="draws in a 3D viewport"):
        bpy.ops.worldpaint.sketch_silhouettes('INVOKE_DEFAULT')


# --- annotations --------------------------------------------------------------------------------------------------

def annotations():
    """The scene's annotations, made if it has none."""
    scene = bpy.context.scene
    data = annotation_data(scene)
    if data is None:
        blend_data = bpy.data.annotations if hasattr(bpy.data, "annotations") else bpy.data.grease_pencils
        data = blend_data.new("Annotations")
        if hasattr(scene, "annotation"):
            scene.annotation = data
        else:
            scene.grease_pencil = data
    return data


def annotate(layer_name, pixels, placement):
    """Draws an annotation stroke through the Annotate tool of the 3D viewport, in camera view (``placement``: 'VIEW'
    or 'CURSOR'), on the layer ``layer_name``; returns the stroke."""
    data = annotations()
    layer = data.layers.get(layer_name) or data.layers.new(layer_name)
    data.layers.active_index = list(data.layers).index(layer)
    window, area, region = view3d_area()
    area.spaces.active.region_3d.view_perspective = 'CAMERA'
    bpy.context.scene.tool_settings.annotation_stroke_placement_view3d = placement
    stroke = [{"name": "", "location": (0.0, 0.0, 0.0), "mouse": xy, "mouse_event": xy, "pressure": 1.0, "size": 0.0,
               "x_tilt": 0.0, "y_tilt": 0.0, "time": float(i), "is_start": i == 0} for i, xy in enumerate(pixels)]
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.gpencil.annotate(mode='DRAW', stroke=stroke, wait_for_input=False) == {'FINISHED'}
    return layer.active_frame.strokes[-1]


def stored(stroke):
    return np.array([tuple(p.co) for p in stroke.points], dtype=np.float64)


def read_annotations(layer_name=""):
    settings = bpy.context.scene.worldpaint.sketch
    settings.source = 'ANNOTATION'
    settings.annotation_layer = layer_name
    return sketch_strokes(bpy.context, settings, sketch_camera(bpy.context, settings))


PIXELS = [(300.0, 420.0), (520.0, 470.0), (760.0, 440.0), (980.0, 510.0)]


def test_an_annotation_placed_in_3d_is_read_as_the_camera_sees_it():
    camera = add_camera()
    scene = bpy.context.scene
    stroke = annotate("Silhouettes", PIXELS, 'CURSOR')
    points = stored(stroke)
    assert len(points) >= 2 and np.any(points[:, 2] != 0.0)
    strokes = read_annotations("Silhouettes")
    expected = [world_to_camera_view(scene, camera, Vector(p)) for p in points]
    expected = np.array([(v.x, v.y) for v in expected if v.z > 0.0])
    assert len(strokes) == 1 and strokes.origins == [("Silhouettes", 0)]
    assert len(expected) >= 2
    assert np.allclose(strokes[0], expected, atol=1e-9)


ROW = [(300.0 + 20.0 * k, 400.0) for k in range(31)]
COLUMN = [(500.0, 200.0 + 20.0 * k) for k in range(26)]


def test_an_annotation_placed_on_the_view_is_read_in_the_camera_frame_it_was_drawn_over():
    set_resolution(1920, 1080)
    camera = add_camera()
    scene = bpy.context.scene
    annotate("Silhouettes", ROW, 'VIEW')
    annotate("Silhouettes", COLUMN, 'VIEW')
    strokes = read_annotations()  # the active layer
    assert len(strokes) == 2
    row, column = strokes

    # Blender keeps a View stroke drawn in camera view in the camera frame: the frame the two strokes reveal has the
    # render's proportions (not the viewport's), half the viewport wide and centred, as the camera view shows it
    # at its default zoom
    _window, _area, region = view3d_area()
    width = (ROW[-1][0] - ROW[0][0]) / (row[-1, 0] - row[0, 0])
    height = (COLUMN[-1][1] - COLUMN[0][1]) / (column[-1, 1] - column[0, 1])
    print(f"camera frame on a {region.width} x {region.height} viewport: {width:.1f} x {height:.1f} px")
    assert width / height == pytest.approx(1920 / 1080, rel=1e-3)
    assert width == pytest.approx(region.width / 2.0, abs=0.5)
    left, bottom = ROW[0][0] - row[0, 0] * width, COLUMN[0][1] - column[0, 1] * height
    assert left + width / 2.0 == pytest.approx(region.width / 2.0, abs=0.5)
    assert bottom + height / 2.0 == pytest.approx(region.height / 2.0, abs=0.5)

    # and the same pixels drawn with Sketch Silhouettes in that view give the same stroke (the Annotate tool smooths
    # its strokes' inner points along the line: the ends and the height are compared)
    view = Region(region.width, region.height)
    rv3d = CameraView(scene, camera, view, (left, bottom, left + width, bottom + height))
    drawn = np.array([region_to_camera(view, rv3d, scene, camera, xy) for xy in ROW])
    assert np.allclose(row[[0, -1]], drawn[[0, -1]], atol=1e-4)
    assert np.allclose(row[:, 1], drawn[0, 1], atol=1e-4)


def test_annotation_strokes_of_one_point_and_unknown_layers_are_reported():
    add_camera()
    annotate("Silhouettes", ROW, 'VIEW')
    annotate("Silhouettes", [ROW[0], ROW[0]], 'VIEW')
    strokes = read_annotations("Silhouettes")
    assert len(strokes) == 1
    assert len(strokes.skipped) == 1 and "annotation stroke 2 of 'Silhouettes' skipped" in strokes.skipped[0]
    with pytest.raises(WorldPaintError, match="No annotation layer called 'Ridges': pick one of Silhouettes"):
        read_annotations("Ridges")


def test_no_annotations_at_all_says_how_to_make_them():
    add_camera()
    with pytest.raises(WorldPaintError, match="The scene has no annotations"):
        read_annotations()


# --- Apply Sketch reads what was drawn ----------------------------------------------------------------------------

def ridges_scene():
    """A near ridge and a far one, and a level camera at the south edge looking north at them (3:2)."""
    from scene_kit import grid_terrain

    cell, n = 4.0, 97
    x, y = np.meshgrid(cell * np.arange(n), cell * np.arange(n))
    heights = np.maximum(15.0 * np.exp(-((y - 90.0) / 12.0) ** 2), 35.0 * np.exp(-((y - 250.0) / 18.0) ** 2))
    terrain = grid_terrain("Terrain", (0.0, 0.0), cell, heights)
    scene = bpy.context.scene
    scene.worldpaint.terrain = terrain
    set_resolution(1200, 800)
    camera = add_camera("Camera")
    camera.data.angle = math.radians(60.0)
    camera.data.clip_end = 2000.0
    camera.location = (192.0, -60.0, 12.0)
    camera.rotation_euler = (math.radians(90.0), 0.0, 0.0)
    bpy.context.view_layer.update()
    return terrain, camera


def test_apply_sketch_orders_the_drawn_strokes_and_leaves_a_one_point_stroke_unranked():
    ridges_scene()
    settings = bpy.context.scene.worldpaint.sketch
    front = [(x, 0.60 + 0.05 * math.sin(math.pi * (x - 0.2) / 0.5)) for x in np.linspace(0.2, 0.7, 25)]
    back = [(x, 0.66 + 0.04 * math.sin(math.pi * (x - 0.62) / 0.3)) for x in np.linspace(0.62, 0.92, 15)]
    draw(back)
    dot = settings.strokes.add()  # a click that a script left behind
    dot.points.add().co = (0.4, 0.4)
    draw(front)
    assert bpy.ops.worldpaint.apply_sketch() == {'FINISHED'}
    ranks = [s.depth_rank for s in settings.strokes]
    print(f"depth ranks of the back stroke, the dot and the front stroke: {ranks}")
    assert ranks[1] == -1
    assert ranks == [1, -1, 0]  # the lower stroke is the near one; the dot is left out
