"""Tools driven by a line dragged over the terrain: the line as a script gives it (the viewport's press, move and
release set the same start and end)."""

import bpy
import pytest
from scene_kit import flat_terrain, hard_core_examples, prototypes, select_only
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects
from worldpaint.ops.drag import stretch_from_drag

REGION = {"region_mode": 'RECT', "rect_min": (0.0, 100.0), "rect_max": (200.0, 200.0)}


def test_a_drag_picks_the_nearest_side_and_its_length_along_the_outward_normal():
    rect = ((0.0, 0.0), (100.0, 50.0))
    assert stretch_from_drag(*rect, (99.0, 20.0), (129.0, 25.0)) == ("EAST", 30.0)
    assert stretch_from_drag(*rect, (1.0, 20.0), (11.0, 20.0)) == ("WEST", -10.0)
    assert stretch_from_drag(*rect, (50.0, 52.0), (50.0, 72.0)) == ("NORTH", 20.0)
    assert stretch_from_drag(*rect, (50.0, -3.0), (40.0, -13.0)) == ("SOUTH", 10.0)


def two_densities():
    bpy.context.scene.worldpaint.terrain = flat_terrain("Flat", size=(300.0, 300.0))
    prototypes()
    settings = bpy.context.scene.worldpaint
    for name, density, corner in (("Sparse", 0.005, (0.0, 0.0)), ("Dense", 0.04, (150.0, 0.0))):
        select_only(hard_core_examples("Tree", corner, 80.0, density, 2.0, 3))
        assert bpy.ops.worldpaint.learn_color(name=name, region_mode='RECT', rect_min=corner,
                                              rect_max=(corner[0] + 80.0, 80.0)) == {'FINISHED'}
        for obj in list(bpy.context.selected_objects):
            bpy.data.objects.remove(obj)
    settings.active_color_index = 0
    settings.gradient_end = "Dense"
    select_only([])


def trees():
    return point_cloud_arrays(point_cloud_objects(bpy.context.scene)["Tree"])[0][:, :2]


def test_a_dragged_line_sets_the_gradients_direction():
    two_densities()
    # dragged from the region's north-east toward its south-west: dense in the south-west
    assert bpy.ops.worldpaint.drag_gradient(start=(190.0, 190.0), end=(10.0, 110.0), **REGION) == {'FINISHED'}
    xy = trees()
    south_west = ((xy[:, 0] < 60.0) & (xy[:, 1] < 130.0)).sum() / (60.0 * 30.0)
    north_east = ((xy[:, 0] > 140.0) & (xy[:, 1] > 170.0)).sum() / (60.0 * 30.0)
    print(f"\ndensity south-west {south_west:.4f}, north-east {north_east:.4f} per m²")
    assert south_west > 3.0 * north_east
    with pytest.raises(RuntimeError, match="Drag a line"):
        bpy.ops.worldpaint.drag_gradient(start=(5.0, 5.0), end=(5.0, 5.0), **REGION)


def test_dragging_a_side_out_stretches_the_region():
    two_densities()
    assert bpy.ops.worldpaint.paste_color(seed=1, **REGION) == {'FINISHED'}
    before = trees()
    assert bpy.ops.worldpaint.drag_stretch(start=(201.0, 150.0), end=(241.0, 160.0), **REGION) == {'FINISHED'}
    after = trees()
    print(f"\n{len(before)} trees -> {len(after)}, east edge {before[:, 0].max():.1f} -> {after[:, 0].max():.1f} m")
    assert after[:, 0].max() > 225.0 and len(after) > len(before)
    with pytest.raises(RuntimeError, match="rectangle"):
        bpy.ops.worldpaint.drag_stretch(start=(0.0, 0.0), end=(5.0, 0.0), region_mode='CURSOR')
