"""The engine's Python surface as the add-on and asset scripts use it: arrays in and out, clear errors, progress."""

import json

import numpy as np
import pytest
import worldpaint_engine as engine

SQUARE = {"shape": "rect", "min": [0.0, 0.0], "max": [50.0, 50.0]}
CATEGORIES = [{"name": "tree"}]


def hard_core_color():
    pts = engine.exemplar_hard_core(SQUARE, 0.04, 2.5, 1)
    scene = engine.Scene(None, CATEGORIES, pts, np.zeros(len(pts), np.int32))
    return engine.learn_color(scene, SQUARE, "trees"), len(pts)


def nothing():
    return engine.Scene(None, CATEGORIES, np.zeros((0, 2)), np.zeros(0, np.int32))


def test_engine_errors_form_one_hierarchy_and_carry_the_engine_message():
    for name in ("InputError", "FileFormatError", "NothingToLearn", "Cancelled", "InternalError"):
        assert issubclass(getattr(engine, name), engine.WorldPaintError), name
    assert issubclass(engine.InputError, ValueError) and not issubclass(engine.Cancelled, ValueError)
    assert all(issubclass(c, engine.InputError) for c in (engine.FileFormatError, engine.NothingToLearn))
    with pytest.raises(engine.InputError, match="region is empty or degenerate"):
        engine.region_area({"shape": "rect", "min": [0, 0], "max": [0, 5]})
    with pytest.raises(engine.InputError, match="unknown region shape 'hexagon'"):
        engine.region_area({"shape": "hexagon"})
    with pytest.raises(engine.InputError, match="missing the key 'radius'"):
        engine.region_area({"shape": "circle", "center": [0, 0]})
    with pytest.raises(engine.InputError, match=r"shape \(N, 3\)"):
        engine.Terrain(np.zeros((4, 2)), np.zeros((1, 3), np.uint32))
    with pytest.raises(engine.InputError, match="category index 3"):
        engine.Scene(None, CATEGORIES, np.zeros((1, 2)), np.array([3], np.int32))
    with pytest.raises(engine.FileFormatError, match="version 99"):
        engine.palette_from_json(json.dumps({"format": "worldpaint-palette", "version": 99, "colors": []}))
    with pytest.raises(engine.NothingToLearn):
        engine.learn_color(nothing(), SQUARE, "empty")


def test_terrain_from_a_mesh_samples_heights_and_maps():
    x, y = np.meshgrid(np.arange(11.0), np.arange(11.0))
    vertices = np.column_stack([x.ravel(), y.ravel(), 0.5 * x.ravel()])
    v0 = (np.arange(10)[None, :] + 11 * np.arange(10)[:, None]).ravel()
    triangles = np.concatenate([np.column_stack([v0, v0 + 1, v0 + 12]), np.column_stack([v0, v0 + 12, v0 + 11])])
    terrain = engine.Terrain(vertices, triangles.astype(np.uint32))
    assert terrain.bbox() == ((0.0, 0.0), (10.0, 10.0))
    z = terrain.heights_at(np.array([[2.5, 3.0], [20.0, 20.0]]))
    assert z[0] == pytest.approx(1.25) and np.isnan(z[1])
    slope = terrain.map_at("slope", np.array([[5.0, 5.0]]))
    assert slope[0] == pytest.approx(np.arctan(0.5), abs=1e-3)
    with pytest.raises(engine.InputError, match="no map 'rainfall'"):
        terrain.map_at("rainfall", np.zeros((1, 2)))


def test_synthesis_reports_progress_and_can_be_cancelled():
    color, _ = hard_core_color()
    seen = []
    out = engine.synthesize(nothing(), color, SQUARE, 1, progress=lambda f: seen.append(f) or True)
    assert len(out["positions"]) > 0 and seen and seen == sorted(seen) and 0.0 <= seen[0] <= seen[-1] <= 1.0
    with pytest.raises(engine.Cancelled):
        engine.synthesize(nothing(), color, SQUARE, 1, progress=lambda f: False)


def test_village_growth_reports_its_stages_by_name_to_a_callback_that_takes_them():
    terrain = engine.exemplar_demo_terrain(200.0, 2.0, 7)
    (x0, y0), (x1, y1) = terrain.bbox()
    region = {"shape": "rect", "min": [x0, y0], "max": [x1, y1]}
    scenario = json.dumps({"events": json.loads(engine.scenario_presets())["presets"]["farming_hamlet"]["events"]})
    staged, plain = [], []
    engine.generate_village(terrain, region, scenario, 1, progress=lambda f, stage: staged.append((f, stage)) or True)
    engine.generate_village(terrain, region, scenario, 1, progress=lambda f: plain.append(f) or True)
    stages = [stage for k, (_, stage) in enumerate(staged) if k == 0 or staged[k - 1][1] != stage]
    assert stages == ["growing the skeleton", "parcels and footprints", "houses"]
    # within a stage the reports come as its parts finish, at least a percent or a tenth of a second apart
    fractions = [f for f, _ in staged]
    assert fractions == sorted(fractions) and plain == sorted(plain), "progress never goes back"
    assert fractions[0] == plain[0] == 0.0 and fractions[-1] == plain[-1] == 1.0
    with pytest.raises(engine.InputError, match=r"unknown argument 'water_levle' \(the surroundings are water_level"):
        engine.generate_village(terrain, region, scenario, 1, water_levle=3.0)


def test_an_exception_in_the_progress_callback_reaches_the_caller():
    color, _ = hard_core_color()

    def broken(_fraction):
        raise KeyError("from the callback")

    with pytest.raises(KeyError, match="from the callback"):
        engine.synthesize(nothing(), color, SQUARE, 1, progress=broken)


def test_same_seed_same_result_and_palette_round_trip():
    color, _ = hard_core_color()
    a = engine.synthesize(nothing(), color, SQUARE, 5)
    b = engine.synthesize(nothing(), color, SQUARE, 5)
    np.testing.assert_array_equal(a["positions"], b["positions"])
    assert engine.palette_from_json(engine.palette_to_json([color, color])) == [color, color]
    summary = engine.color_summary(color)
    assert summary["name"] == "trees" and summary["preview"].shape[1] == 3


def test_region_contains_all_shapes():
    xy = np.array([[1.0, 1.0], [9.0, 9.0], [20.0, 20.0]])
    circle = {"shape": "circle", "center": [0.0, 0.0], "radius": 5.0}
    polygon = {"shape": "polygon", "points": [[0, 0], [10, 0], [10, 10], [0, 10]]}
    assert engine.region_contains(circle, xy).tolist() == [True, False, False]
    assert engine.region_contains(polygon, xy).tolist() == [True, True, False]
    assert engine.region_area(polygon) == pytest.approx(100.0)


def test_input_past_the_limits_is_refused_before_anything_is_allocated():
    # a shared color file with one absurd number: refused when it is read, naming the field
    color, _ = hard_core_color()
    doc = json.loads(color)["color"]
    doc["categories"][0]["density"] = 1e6
    palette = json.dumps({"format": "worldpaint-palette", "version": 1, "colors": [doc]})
    with pytest.raises(engine.FileFormatError, match=r"colors\[0\].*categories\[0\]\.density"):
        engine.palette_from_json(palette)
    # a terrain of 1e10 cells given as a broadcast array (which costs Python nothing)
    with pytest.raises(engine.InputError, match="too large: the terrain grid"):
        engine.Terrain.from_grid((0.0, 0.0), 1.0, np.broadcast_to(np.float64(0.0), (100_000, 100_000)))
    # a region nested 10,000 deep
    region = SQUARE
    for _ in range(10_000):
        region = {"shape": "clipped", "within": [region]}
    with pytest.raises(engine.InputError, match="nesting"):
        engine.region_area(region)


def test_array_arguments_take_float32_and_integer_arrays_for_float64():
    # values every dtype holds exactly, so each must give the float64 result
    xy = np.array([[1.0, 1.0], [9.0, 9.0], [60.0, 2.0], [-3.0, 20.0]])
    for dtype in (np.float32, np.int32, np.int64, np.uint16):
        assert engine.region_contains(SQUARE, xy.astype(dtype)).tolist() == [True, True, False, False], dtype
    assert engine.region_contains(SQUARE, xy.tolist()).tolist() == [True, True, False, False]

    heights = np.arange(20.0).reshape(4, 5)
    probe = np.array([[1.5, 2.0], [3.0, 0.5]])
    expected = engine.Terrain.from_grid((0.0, 0.0), 1.0, heights).heights_at(probe)
    for dtype in (np.float32, np.int16):
        terrain = engine.Terrain.from_grid((0.0, 0.0), 1.0, heights.astype(dtype))
        np.testing.assert_array_equal(terrain.heights_at(probe.astype(np.float32)), expected, err_msg=str(dtype))
    x, y = np.meshgrid(np.arange(5.0), np.arange(5.0))
    vertices = np.column_stack([x.ravel(), y.ravel(), x.ravel() + 2 * y.ravel()])
    v0 = (np.arange(4)[None, :] + 5 * np.arange(4)[:, None]).ravel()
    triangles = np.concatenate([np.column_stack([v0, v0 + 1, v0 + 6]), np.column_stack([v0, v0 + 6, v0 + 5])])
    expected = engine.Terrain(vertices, triangles.astype(np.uint32)).heights_at(probe)
    mesh = engine.Terrain(vertices.astype(np.float32), triangles.astype(np.int64))
    np.testing.assert_array_equal(mesh.heights_at(probe.astype(np.float32)), expected)
    np.testing.assert_array_equal(mesh.heights_at(np.array([[1, 2], [3, 1]])), [5.0, 5.0])

    color, _ = hard_core_color()
    positions = np.round(engine.exemplar_hard_core(SQUARE, 0.04, 2.5, 3) * 4) / 4  # quarters: exact in float32
    n = len(positions)
    before = engine.Scene(None, CATEGORIES, positions, np.zeros(n, np.int32), rotations=np.zeros(n),
                          locked=np.zeros(n, bool))
    after = engine.Scene(None, CATEGORIES, positions.astype(np.float32), np.zeros(n, np.int64),
                         rotations=np.zeros(n, np.float32), locked=np.zeros(n, np.uint8))
    half = {"shape": "rect", "min": [0.0, 0.0], "max": [25.0, 50.0]}
    a, b = engine.paste(before, color, half, 4), engine.paste(after, color, half, 4)
    assert len(a["removed"]) > 0 and len(a["positions"]) > 0
    np.testing.assert_array_equal(a["removed"], b["removed"])
    np.testing.assert_array_equal(a["positions"], b["positions"])


def test_an_unusable_array_argument_raises_input_error_naming_it():
    # the wrong number of columns keeps its message; any other shape or a dtype that is not numbers says what came
    with pytest.raises(engine.InputError, match=r"^invalid input: xy must have shape \(N, 2\), got \(N, 3\)$"):
        engine.region_contains(SQUARE, np.zeros((5, 3), np.float32))
    with pytest.raises(engine.InputError, match=r"xy: expected an \(N, 2\) array of numbers, "
                                                r"got a float32 array of shape \(5,\)$"):
        engine.region_contains(SQUARE, np.zeros(5, np.float32))
    with pytest.raises(engine.InputError, match=r"positions: expected an \(N, 2\) array of numbers, "
                                                r"got a string array of shape \(3, 2\)$"):
        engine.Scene(None, CATEGORIES, np.full((3, 2), "1.5"), np.zeros(3, np.int32))
    with pytest.raises(engine.InputError, match=r"category_index: expected an \(N,\) array of integers, "
                                                r"got a float64 array of shape \(3,\)$"):
        engine.Scene(None, CATEGORIES, np.zeros((3, 2)), np.zeros(3))
    with pytest.raises(engine.InputError, match=r"rotations: expected an \(N,\) array of numbers, got an object array"):
        engine.Scene(None, CATEGORIES, np.zeros((3, 2)), np.zeros(3, np.int32), rotations=np.array([0.0, None, 1.0]))
    with pytest.raises(engine.InputError, match=r"triangles: expected an \(N, 3\) array of integers from 0 to "
                                                r"4294967295, got the value -1$"):
        engine.Terrain(np.zeros((3, 3)), np.array([[0, 1, -1]]))
    with pytest.raises(engine.InputError, match=r"heights: expected a 2-D array of numbers, got None$"):
        engine.Terrain.from_grid((0.0, 0.0), 1.0, None)
    with pytest.raises(engine.InputError, match=r"path: expected an \(N, 2\) array of numbers, got a list numpy "
                                                r"cannot read as an array"):
        engine.Stroke(nothing(), erase=True).follow([[0.0, 0.0], [1.0]])
    with pytest.raises(engine.InputError, match=r"contour 1: expected an \(N, 2\) array of numbers, "
                                                r"got a complex128 array of shape \(3, 2\)$"):
        engine.fill_polygons([np.zeros((3, 2)), np.zeros((3, 2), complex)], 1.0)
    # a float32 broadcast grid past the limit is refused before the cast would copy it
    with pytest.raises(engine.InputError, match="too large: the terrain grid"):
        engine.Terrain.from_grid((0.0, 0.0), 1.0, np.broadcast_to(np.float32(0.0), (100_000, 100_000)))
