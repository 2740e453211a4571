"""The interaction matrix set before learning: a pair switched to None is learned and painted as independent."""

import bpy
import numpy as np
import pytest
from scene_kit import flat_terrain, hard_core_examples, prototypes, select_only, slope_exemplar
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

EXEMPLAR = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (100.0, 100.0)}
DESTINATION = {"region_mode": 'RECT', "rect_min": (0.0, 100.0), "rect_max": (200.0, 200.0)}
LOW, HIGH = np.array([0.0, 100.0]), np.array([200.0, 200.0])
RINGS = np.arange(0.0, 10.5, 1.0)


def pasted(seed):
    assert bpy.ops.worldpaint.paste_color(seed=seed, **DESTINATION) == {'FINISHED'}
    clouds = point_cloud_objects(bpy.context.scene)
    return {name: point_cloud_arrays(clouds[name])[0][:, :2] for name in ("Rock", "Grass")}


def cross_pcf(centres, others):
    """The cross pair-correlation of ``others`` around ``centres`` in rings to 10 m, from the centres at least 10 m
    inside the destination (no edge correction needed)."""
    inner = centres[np.all((centres >= LOW + RINGS[-1]) & (centres <= HIGH - RINGS[-1]), axis=1)]
    distances = np.linalg.norm(inner[:, None, :] - others[None, :, :], axis=2)
    counts, _ = np.histogram(distances, bins=RINGS)
    intensity = len(others) / np.prod(HIGH - LOW)
    return counts / (len(inner) * intensity * np.pi * np.diff(RINGS ** 2))


def deviation(pcf):
    return float(np.sqrt(np.mean((pcf - 1.0) ** 2)))


def test_a_pair_set_to_none_before_learning_is_painted_independent():
    _, examples, _ = slope_exemplar()
    settings = bpy.context.scene.worldpaint
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Clumped", **EXEMPLAR) == {'FINISHED'}
    # the matrix cell: a click goes Auto -> None -> Oriented -> Auto
    for expected in ("NONE", "ORIENTED", "AUTO", "NONE"):
        assert bpy.ops.worldpaint.set_learn_relation(category="Grass", other="Rock") == {'FINISHED'}
        assert settings.learn_relation("Grass", "Rock") == expected
    select_only(examples)
    # what the Learn Color button passes from the matrix
    assert bpy.ops.worldpaint.learn_color(name="Independent", independent=settings.learn_pairs("NONE"),
                                          **EXEMPLAR) == {'FINISHED'}
    entry = settings.palette["Independent"]
    assert [(i.category, i.other) for i in entry.interactions if not i.enabled] == [("Grass", "Rock")]

    select_only([])
    settings.active_color_index = 0
    clumped = pasted(seed=5)
    clumped_pcf = cross_pcf(clumped["Rock"], clumped["Grass"])
    settings.active_color_index = 1
    # three draws each: the cross pcf of one draw of clumped grass is noisy (its RMS ranged over 0.26-0.87 here)
    independent, reference = [], []
    for seed in (5, 7, 9):
        drawn, second_draw = pasted(seed=seed), pasted(seed=seed + 1)
        independent.append(deviation(cross_pcf(drawn["Rock"], drawn["Grass"])))
        # grass of another draw around these rocks: independent by construction, with the same slope preference
        reference.append(deviation(cross_pcf(drawn["Rock"], second_draw["Grass"])))
    independent, reference = float(np.mean(independent)), float(np.mean(reference))
    print(f"\ngrass around rocks, pcf - 1 RMS over 0-10 m: learned {deviation(clumped_pcf):.3f}, "
          f"set to none {independent:.3f}, a second draw {reference:.3f} (means of three draws)")
    assert deviation(clumped_pcf) > 2.0 * reference, "the example's grass clusters around its rocks"
    assert independent <= 1.5 * reference + 0.05


def test_bad_matrix_cells_and_pairs_are_clear_errors():
    _, examples, _ = slope_exemplar()
    select_only(examples)
    bpy.ops.worldpaint.find_categories()
    with pytest.raises(RuntimeError, match="Only two distributions"):
        bpy.ops.worldpaint.set_learn_relation(category="Grass", other="slope", how='ORIENTED')
    with pytest.raises(RuntimeError, match="no interaction between Grass and Castle"):
        bpy.ops.worldpaint.learn_color(independent="Grass:Castle", **EXEMPLAR)
    with pytest.raises(RuntimeError, match="not of the form"):
        bpy.ops.worldpaint.learn_color(independent="Grass", **EXEMPLAR)
    assert len(bpy.context.scene.worldpaint.palette) == 0


def test_a_colors_own_iterations_and_influence_are_used_when_it_is_pasted():
    _, examples, _ = slope_exemplar()
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Forest", **EXEMPLAR) == {'FINISHED'}
    select_only([])
    entry = bpy.context.scene.worldpaint.palette["Forest"]
    figures = {}
    for iterations in (0.0, 1.0):
        entry.iterations_per_instance = iterations
        assert bpy.ops.worldpaint.paste_color(seed=5, **DESTINATION) == {'FINISHED'}
        clouds = point_cloud_objects(bpy.context.scene)
        figures[iterations] = {name: len(point_cloud_arrays(obj)[0]) for name, obj in clouds.items()}
        figures[iterations]["Grass near rocks"] = deviation(cross_pcf(*pasted_pair()))
    print(f"\ndefault iterations: {figures[0.0]}; one per instance: {figures[1.0]}")
    # one proposal per instance leaves the grass far from clustering around the rocks as the example does
    assert figures[1.0]["Grass near rocks"] < 0.5 * figures[0.0]["Grass near rocks"]


def test_a_colors_own_region_of_influence_decides_whether_a_paste_sees_its_neighbour():
    bpy.context.scene.worldpaint.terrain = flat_terrain("Flat", size=(300.0, 200.0))
    prototypes()
    select_only(hard_core_examples("Tree", (0.0, 0.0), 100.0, 0.04, 3.0, 4))
    assert bpy.ops.worldpaint.learn_color(name="Hard core", **EXEMPLAR) == {'FINISHED'}
    select_only([])
    entry = bpy.context.scene.worldpaint.palette["Hard core"]
    closest = {}
    for influence in (-1.0, 0.0):  # the panel's (automatic: the color's interaction radius), then none
        entry.influence_radius = influence
        for rect_min, rect_max in (((0.0, 100.0), (100.0, 200.0)), ((100.0, 100.0), (200.0, 200.0))):
            assert bpy.ops.worldpaint.paste_color(seed=5, region_mode='RECT', rect_min=rect_min,
                                                  rect_max=rect_max) == {'FINISHED'}
        trees = point_cloud_arrays(point_cloud_objects(bpy.context.scene)["Tree"])[0][:, :2]
        west, east = trees[trees[:, 0] < 100.0], trees[trees[:, 0] >= 100.0]
        closest[influence] = np.linalg.norm(west[:, None, :] - east[None, :, :], axis=2).min()
    print(f"\nclosest trees across the seam: {closest[-1.0]:.2f} m with the automatic influence, "
          f"{closest[0.0]:.2f} m with none")
    assert closest[-1.0] >= 3.0 > closest[0.0]


def pasted_pair():
    clouds = point_cloud_objects(bpy.context.scene)
    return (point_cloud_arrays(clouds["Rock"])[0][:, :2], point_cloud_arrays(clouds["Grass"])[0][:, :2])
