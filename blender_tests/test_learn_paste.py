"""A forest learned from a hand-made example on a slope, pasted elsewhere through the operators, as a user would."""

import json

import bpy
import numpy as np
import pytest
import worldpaint_engine as engine
from scene_kit import select_only, slope_exemplar
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

EXEMPLAR = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (100.0, 100.0)}
DESTINATION = {"region_mode": 'RECT', "rect_min": (0.0, 100.0), "rect_max": (200.0, 200.0)}
DESTINATION_AREA = 200.0 * 100.0


def learn_slope_color():
    terrain_obj, examples, data = slope_exemplar()
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Slope forest", **EXEMPLAR) == {'FINISHED'}
    return terrain_obj, examples, data


def synthesized_points():
    """{category: (co (N, 3), rotation, scale, prototype)} of the scene's point clouds."""
    return {c: point_cloud_arrays(obj) for c, obj in point_cloud_objects(bpy.context.scene).items()}


def test_learn_color_adds_a_palette_color_with_its_categories_and_preview():
    learn_slope_color()
    settings = bpy.context.scene.worldpaint
    assert [c.name for c in settings.palette] == ["Slope forest"]
    color = settings.palette[0]
    summary = engine.color_summary(color.json)
    assert {c["name"] for c in summary["categories"]} == {"Tree", "Rock", "Grass"}
    assert {c.name for c in settings.categories} == {"Tree", "Rock", "Grass"}
    image = bpy.data.images[color.preview_image]
    assert tuple(image.size) == (64, 64) and image.packed_file is not None
    pixels = np.empty(64 * 64 * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    assert pixels.reshape(-1, 4)[:, :3].std(axis=0).max() > 0.02, "the preview shows the exemplar's points"


def test_pasted_forest_has_the_exemplar_density_and_slope_preference():
    terrain_obj, _, data = learn_slope_color()
    color_json = bpy.context.scene.worldpaint.palette[0].json
    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=7, **DESTINATION) == {'FINISHED'}

    points = synthesized_points()
    assert set(points) == {"Tree", "Rock", "Grass"}
    reference = {c["name"]: c for c in engine.color_summary(color_json)["categories"]}
    for category, (co, *_rest) in points.items():
        expected = reference[category]["density"] * DESTINATION_AREA
        assert abs(len(co) - expected) <= 0.15 * expected, f"{category}: {len(co)} pasted, {expected:.0f} expected"
        inside = (co[:, 1] >= 100.0) & (co[:, 1] <= 200.0) & (co[:, 0] >= 0.0) & (co[:, 0] <= 200.0)
        assert inside.all(), f"{category}: instances outside the destination"

    # re-learn the pasted result as a color and compare it with the exemplar's color through the engine
    categories = [{"name": n, "priority": i} for i, n in enumerate(["Tree", "Rock", "Grass"])]
    xy = np.concatenate([points[c["name"]][0][:, :2] for c in categories])
    index = np.concatenate([np.full(len(points[c["name"]][0]), i, np.int32) for i, c in enumerate(categories)])
    region = {"shape": "rect", "min": [0.0, 100.0], "max": [200.0, 200.0]}
    pasted = engine.learn_color(engine.Scene(data["terrain"], categories, np.ascontiguousarray(xy), index), region,
                                "pasted")
    fidelity = engine.compare(color_json, pasted)
    for category, ratio in fidelity["density_ratio"].items():
        assert abs(ratio - 1.0) <= 0.15, f"{category}: density ratio {ratio:.2f}"
    # slope histograms: a category seen fewer than 50 times in the exemplar (the ~20 rocks) has a histogram too
    # noisy for a 0.2 bound (two independent draws of 20 points already differ by about that much)
    well_sampled = {c["name"] for c in reference.values() if c["count"] >= 50}
    slope_tv = {c: tv for c, m, tv in fidelity["map_tv"] if m == "slope" and c in well_sampled}
    assert {"Tree", "Grass"} <= set(slope_tv) and max(slope_tv.values()) <= 0.2, f"slope histogram TV {slope_tv}"


def test_trees_stay_on_the_slopes_they_were_learned_on():
    _, _, data = learn_slope_color()
    select_only([])
    bpy.ops.worldpaint.paste_color(seed=3, **DESTINATION)
    co = synthesized_points()["Tree"][0]
    slope = np.degrees(data["terrain"].map_at("slope", np.ascontiguousarray(co[:, :2])))
    # the exemplar's trees stand on 20-35 degree slopes; allow a little for the histogram's bin width
    assert np.mean((slope > 17.0) & (slope < 38.0)) >= 0.95, f"slopes of pasted trees: {np.percentile(slope, [5, 95])}"


def test_instances_sit_on_the_terrain_and_the_instancer_really_instances():
    terrain_obj, _, _ = learn_slope_color()
    select_only([])
    bpy.ops.worldpaint.paste_color(seed=1, **DESTINATION)
    clouds = point_cloud_objects(bpy.context.scene)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    counts = {name: 0 for name in clouds}
    z_error = []
    for inst in depsgraph.object_instances:
        if not inst.is_instance or inst.parent is None:
            continue
        category = inst.parent.original.get("wp_points")
        if category is None:
            continue
        counts[category] += 1
        location = inst.matrix_world.translation
        hit, where, *_ = terrain_obj.ray_cast((location.x, location.y, 1000.0), (0.0, 0.0, -1.0))
        assert hit, "every instance stands above the terrain"
        z_error.append(abs(location.z - where.z))
    for name, obj in clouds.items():
        assert counts[name] == len(obj.data.vertices) > 0, f"{name}: {counts[name]} instances for its points"
        modifier = obj.modifiers["WorldPaint"]
        assert modifier.node_group.name == "WorldPaint Instancer"
        assert obj.users_collection[0].name == "WorldPaint"
    assert max(z_error) < 0.01, f"instances float or sink: worst {max(z_error):.4f} m"


def test_instances_take_rotation_and_scale_from_the_point_attributes():
    learn_slope_color()
    select_only([])
    bpy.ops.worldpaint.paste_color(seed=2, **DESTINATION)
    co, rotation, scale, _ = synthesized_points()["Tree"]
    want = {(round(x, 2), round(y, 2)): (r, s) for (x, y, _z), r, s in zip(co, rotation, scale, strict=True)}
    seen = 0
    for inst in bpy.context.evaluated_depsgraph_get().object_instances:
        if inst.is_instance and inst.parent is not None and inst.parent.original.get("wp_points") == "Tree":
            t = inst.matrix_world.translation
            r, s = want[(round(t.x, 2), round(t.y, 2))]
            got_rotation = inst.matrix_world.to_euler().z % (2 * np.pi)
            assert abs(np.angle(np.exp(1j * (got_rotation - r)))) < 1e-3
            assert inst.matrix_world.to_scale().x == pytest.approx(s, rel=1e-4)
            seen += 1
    assert seen == len(co)


def test_paste_replaces_synthesized_points_inside_the_region_and_keeps_the_rest():
    learn_slope_color()
    select_only([])
    bpy.ops.worldpaint.paste_color(seed=1, **DESTINATION)
    first = synthesized_points()
    small = {"region_mode": 'CIRCLE', "circle_center": (100.0, 150.0), "circle_radius": 30.0}
    bpy.ops.worldpaint.paste_color(seed=2, **small)
    second = synthesized_points()
    for category in first:
        old, new = first[category][0], second[category][0]
        outside_old = old[np.hypot(old[:, 0] - 100.0, old[:, 1] - 150.0) > 30.0]
        outside_new = new[np.hypot(new[:, 0] - 100.0, new[:, 1] - 150.0) > 30.0]
        np.testing.assert_allclose(outside_new, outside_old, err_msg=f"{category}: points outside were touched")
        inside_old = old[np.hypot(old[:, 0] - 100.0, old[:, 1] - 150.0) <= 30.0]
        inside_new = new[np.hypot(new[:, 0] - 100.0, new[:, 1] - 150.0) <= 30.0]
        if len(inside_old) and len(inside_new):
            assert not np.array_equal(inside_old, inside_new), f"{category}: the circle was not repainted"


def test_clear_region_removes_only_the_points_inside():
    learn_slope_color()
    select_only([])
    bpy.ops.worldpaint.paste_color(seed=1, **DESTINATION)
    before = synthesized_points()
    clear = {"region_mode": 'RECT', "rect_min": (0.0, 100.0), "rect_max": (100.0, 200.0)}
    assert bpy.ops.worldpaint.clear_region(**clear) == {'FINISHED'}
    after = synthesized_points()
    for category in before:
        old, new = before[category][0], after[category][0]
        assert (new[:, 0] > 100.0).all(), f"{category}: points left in the cleared region"
        assert len(new) == int((old[:, 0] > 100.0).sum())


def test_learn_and_paste_with_curve_and_cursor_regions():
    terrain_obj, examples, _ = learn_slope_color()
    scene = bpy.context.scene
    from scene_kit import closed_circle_curve

    curve = closed_circle_curve("ExampleBoundary", (50.0, 50.0), 40.0)
    select_only(examples + [curve])
    bpy.context.view_layer.objects.active = curve
    assert bpy.ops.worldpaint.learn_color(name="Curve color", region_mode='CURVE') == {'FINISHED'}
    summary = engine.color_summary(scene.worldpaint.palette["Curve color"].json)
    assert summary["region"]["shape"] == "polygon"
    assert summary["region_area"] == pytest.approx(np.pi * 40.0**2, rel=0.02)

    scene.cursor.location = (150.0, 150.0, 0.0)
    scene.worldpaint.region_mode = 'CURSOR'
    scene.worldpaint.region_radius = 25.0
    select_only([])
    assert bpy.ops.worldpaint.paste_color() == {'FINISHED'}
    for co, *_ in synthesized_points().values():
        assert (np.hypot(co[:, 0] - 150.0, co[:, 1] - 150.0) <= 25.0 + 1e-6).all()


def test_selection_region_is_the_default():
    _, examples, _ = learn_slope_color()
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="From selection") == {'FINISHED'}
    summary = engine.color_summary(bpy.context.scene.worldpaint.palette["From selection"].json)
    (x0, y0), (x1, y1) = summary["region"]["min"], summary["region"]["max"]
    assert 0.0 <= x0 < 3.0 and 97.0 < x1 <= 100.0 and 0.0 <= y0 < 3.0 and 97.0 < y1 <= 100.0


def test_a_color_pastes_on_higher_ground_and_learns_heights_only_when_asked(capfd):
    terrain_obj, examples, _ = slope_exemplar()
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Anywhere", **EXEMPLAR) == {'FINISHED'}
    assert bpy.ops.worldpaint.learn_color(name="Lowland", use_elevation=True, **EXEMPLAR) == {'FINISHED'}
    palette = bpy.context.scene.worldpaint.palette

    def learned_maps(name):
        return {m["map"] for m in json.loads(palette[name].json)["color"]["maps"]}

    assert learned_maps("Anywhere") == {"slope"}
    assert learned_maps("Lowland") == {"slope", "elevation"}

    terrain_obj.location.z += 300.0  # the same slopes, 300 m higher than any example
    bpy.context.view_layer.update()
    select_only([])
    assert bpy.ops.worldpaint.paste_color(color="Anywhere", seed=3, **DESTINATION) == {'FINISHED'}
    counts = {c: len(p[0]) for c, p in synthesized_points().items()}
    assert counts.get("Tree", 0) > 20 and counts.get("Grass", 0) > 20, counts

    # a color that learned heights says the destination lies above all of them, and paints no more there than
    # its example's mean density: what the height-blind color paints on the same slopes, give or take
    capfd.readouterr()
    assert bpy.ops.worldpaint.paste_color(color="Lowland", seed=3, **DESTINATION) == {'FINISHED'}
    assert "100% of it has elevation outside what it showed" in capfd.readouterr().out
    lowland = {c: len(p[0]) for c, p in synthesized_points().items()}
    for category, n in counts.items():
        assert lowland.get(category, 0) <= 1.1 * n + 5, (category, lowland, counts)
