"""Tools restricted to the active layer: erasing, clearing and pasting change its categories and leave the others'
content exactly as it was."""

import bpy
import numpy as np
from scene_kit import select_only, slope_exemplar
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

EXEMPLAR = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (100.0, 100.0)}
DESTINATION = {"region_mode": 'RECT', "rect_min": (0.0, 100.0), "rect_max": (200.0, 200.0)}


def clouds():
    return {name: point_cloud_arrays(obj)[0] for name, obj in point_cloud_objects(bpy.context.scene).items()}


def painted_forest_in_two_layers():
    _, examples, _ = slope_exemplar()
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Forest", **EXEMPLAR) == {'FINISHED'}
    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=2, **DESTINATION) == {'FINISHED'}
    settings = bpy.context.scene.worldpaint
    for category in settings.categories:
        category.layer = "trees" if category.name == "Tree" else "ground"
    settings.active_layer, settings.layer_only = "ground", True
    return settings


def test_a_layer_restricted_erase_leaves_the_other_layers_untouched():
    painted_forest_in_two_layers()
    before = clouds()
    stroke = [{"name": "", "location": (x, 150.0, 0.0)} for x in np.linspace(20.0, 180.0, 17)]
    assert bpy.ops.worldpaint.erase(stroke=stroke, radius=30.0) == {'FINISHED'}
    after = clouds()
    print("\nerased on layer 'ground': " + ", ".join(f"{c} {len(before[c])} -> {len(after[c])}" for c in before))
    assert np.array_equal(after["Tree"], before["Tree"]), "the trees' layer is untouched"
    for category in ("Rock", "Grass"):
        xy = after[category][:, :2]
        on_stroke = np.column_stack([np.clip(xy[:, 0], 20.0, 180.0), np.full(len(xy), 150.0)])
        near = np.linalg.norm(xy - on_stroke, axis=1) < 29.0
        assert len(after[category]) < 0.75 * len(before[category]) and not near.any()


def test_clear_and_paste_on_the_active_layer_keep_the_other_layers():
    settings = painted_forest_in_two_layers()
    trees = clouds()["Tree"]
    assert bpy.ops.worldpaint.clear_region(**DESTINATION) == {'FINISHED'}
    after = clouds()
    assert np.array_equal(after["Tree"], trees) and len(after["Rock"]) == len(after["Grass"]) == 0
    assert bpy.ops.worldpaint.paste_color(seed=3, **DESTINATION) == {'FINISHED'}
    after = clouds()
    assert np.array_equal(after["Tree"], trees) and len(after["Rock"]) > 0 and len(after["Grass"]) > 0
    # the trees' layer active, the same paste replaces the trees only
    settings.active_layer = "trees"
    ground = {c: after[c] for c in ("Rock", "Grass")}
    assert bpy.ops.worldpaint.paste_color(seed=4, **DESTINATION) == {'FINISHED'}
    after = clouds()
    assert all(np.array_equal(after[c], ground[c]) for c in ground)
    assert len(after["Tree"]) > 0 and not np.array_equal(after["Tree"], trees)
    settings.active_layer = "water"
    assert len(settings.palette) == 1
    try:
        bpy.ops.worldpaint.paste_color(seed=5, **DESTINATION)
        raise AssertionError("pasting with no category in the active layer is refused")
    except RuntimeError as exc:
        assert "active layer 'water'" in str(exc)
