"""A world painted from a map on the command line: an .asc of labels and a legend naming the palette's colors, run
on Dask; the same bytes with one worker and with two, each color's own density away from the boundary and a blend
across it, and every bad map refused with one line before any tile runs."""

import json

import numpy as np
import pytest
import worldpaint_engine as engine
from bench_world import EXEMPLAR, bench_color
from test_world_cli import assert_refused, cli, snapshot
from worldpaint_engine import world

pytest.importorskip("distributed", reason="filling worlds needs dask[distributed]")

SIDE = 400.0
MAP_CELL = 20.0
BOUNDARY = 200.0
MEADOW_DENSITY = 0.01


def meadow_color():
    """Scattered bushes, 0.01 per m², of a category the benchmark color does not have."""
    bushes = engine.exemplar_uniform(EXEMPLAR, MEADOW_DENSITY, 4)
    categories = [{"name": "Bush", "layer": "vegetation", "kind": "distribution", "priority": 0}]
    scene = engine.Scene(None, categories, bushes, np.zeros(len(bushes), np.int32))
    return engine.learn_color(scene, EXEMPLAR, "Meadow")


def write_label_asc(path, labels, cell=MAP_CELL, corner=(0.0, 0.0), extra=""):
    """``labels`` (rows along +Y) as an ESRI ASCII grid, rows from the north."""
    ny, nx = labels.shape
    header = f"ncols {nx}\nnrows {ny}\nxllcorner {corner[0]:g}\nyllcorner {corner[1]:g}\ncellsize {cell:g}\n{extra}"
    rows = "\n".join(" ".join(str(v) for v in row) for row in labels[::-1])
    path.write_text(header + rows + "\n")
    return path


def two_labels(n=int(SIDE / MAP_CELL)):
    """Label 1 (the benchmark color) west of x = 200 m, label 2 (meadow) east of it."""
    return np.where((np.arange(n)[None, :] + 0.5) * MAP_CELL < BOUNDARY, 1, 2).repeat(n, axis=0)


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("map_inputs")
    palette = folder / "palette.json"
    palette.write_text(engine.palette_to_json([bench_color(), meadow_color()]))
    labels = write_label_asc(folder / "labels.asc", two_labels())
    legend = folder / "legend.json"
    legend.write_text(json.dumps({"1": "Bench", "2": "Meadow"}))
    return {"palette": palette, "map": labels, "legend": legend, "folder": folder}



def test_a_map_world_has_each_color_on_its_side_a_blend_between_and_the_same_bytes_on_one_or_two_workers(
        inputs, tmp_path):
    runs = {}
    for workers in (1, 2):
        out = tmp_path / f"world{workers}"
        run = cli("--palette", inputs["palette"], "--map", inputs["map"], "--legend", inputs["legend"], "--region", 0,
                  0, SIDE, SIDE, "--tile", 100, "--seed", 3, "--out", out, "--workers", workers, "--quiet")
        assert run.returncode == 0, run.stderr
        runs[workers] = snapshot(out)
    assert runs[1] == runs[2], "one and two workers filled different worlds"
    manifest = world.read_manifest(tmp_path / "world2")
    assert manifest["colors"] == ["Bench", "Meadow"]
    assert [c["name"] for c in manifest["categories"]] == ["Tree", "Rock", "Grass", "Bush"]
    xy, category = [], []
    for t in manifest["tiles"]:
        tile = engine.read_world_tile((tmp_path / "world2" / t["file"]).read_bytes())
        assert tile["categories"] == ["Tree", "Rock", "Grass", "Bush"]
        xy.append(tile["positions"])
        category.append(tile["category_index"])
    xy, category = np.concatenate(xy), np.concatenate(category)

    def density(x0, x1, bush):
        inside = (xy[:, 0] >= x0) & (xy[:, 0] < x1) & ((category == 3) == bush)
        return inside.sum() / ((x1 - x0) * SIDE)

    # away from the band (three regions of influence wide, about 55 m): each color's own density
    west, east = density(0.0, 120.0, False), density(280.0, SIDE, True)
    print(f"west {west:.4f} per m² (Bench 0.1), east {east:.4f} (Meadow {MEADOW_DENSITY})")
    assert abs(west / 0.1 - 1.0) < 0.1 and abs(east / MEADOW_DENSITY - 1.0) < 0.2
    assert density(0.0, 120.0, True) == 0.0 and density(280.0, SIDE, False) == 0.0
    # on the boundary, both, each below its own color's density
    assert 0.02 < density(190.0, 210.0, False) < 0.08 and 0.002 < density(190.0, 210.0, True) < 0.008


# (case, arguments replacing the map's, words the one line holds)
BAD_MAPS = [
    ("label with no legend entry", {"legend": {"1": "Bench"}},
     ["the map: its label 2 (first at x 210.0, y 10.0) has no legend entry"]),
    ("color missing from the palette", {"legend": {"1": "Bench", "2": "Orchard"}},
     ["legend.json", "'Orchard'", "palette does not have", "Bench, Meadow"]),
    ("label not a number", {"legend": {"one": "Bench", "2": "Meadow"}}, ["legend.json", "'one'", "whole number"]),
    ("legend not JSON", {"legend_text": "{1: Bench"}, ["legend.json", "not JSON"]),
    ("legend a list", {"legend": ["Bench", "Meadow"]}, ["legend.json", "JSON object"]),
    ("map smaller than the region", {"labels": two_labels(10)},
     ["the map: covers x 0.0..200.0, y 0.0..200.0, not the whole world"]),
    ("fractional label", {"labels": two_labels() + 0.5},
     ["labels.asc", "label 1.5 (column 0, row 0 from the south)", "whole number"]),
    ("negative label", {"labels": -two_labels()}, ["labels.asc", "label -1 (column 0", "whole number"]),
    ("no-data cells", {"labels": np.where(two_labels() == 2, -9999, 1), "extra": "NODATA_value -9999\n"},
     ["labels.asc", "no-data", "needs a label"]),
    ("map of another kind", {"map_name": "labels.png"}, ["--map", "labels.png", ".asc or .npy"]),
    ("map missing", {"map_name": "missing.asc", "skip_write": True}, ["missing.asc", "No such file"]),
    ("npy of other proportions", {"npy": np.ones((10, 20), np.int32)}, ["labels.npy", "not be square"]),
    ("map without a legend", {"no_legend": True},
     ["--map", 'needs its --legend (a JSON file {"label": "color name"})']),
    ("legend without a map", {"no_map": True}, ["--legend", "describes a --map"]),
    ("band without a map", {"no_map": True, "no_legend": True, "band": 10}, ["--band", "describes a --map"]),
    ("negative band", {"band": -5}, ["--band", "-5", "0 or more"]),
    ("map and color", {"color": "Bench"}, ["--color", "not allowed with argument --map"]),
]


@pytest.mark.parametrize("case, change, words", BAD_MAPS, ids=[c[0] for c in BAD_MAPS])
def test_a_bad_map_is_refused_with_one_line_before_any_tile(inputs, tmp_path, case, change, words):
    legend = tmp_path / "legend.json"
    legend.write_text(change.get("legend_text") or json.dumps(change.get("legend", {"1": "Bench", "2": "Meadow"})))
    if "npy" in change:
        labels = tmp_path / "labels.npy"
        np.save(labels, change["npy"])
    else:
        labels = tmp_path / change.get("map_name", "labels.asc")
        if not change.get("skip_write"):
            write_label_asc(labels, change.get("labels", two_labels()), extra=change.get("extra", ""))
    args = ["--palette", inputs["palette"], "--region", 0, 0, SIDE, SIDE, "--tile", 100, "--quiet"]
    args += [] if change.get("no_map") else ["--map", labels]
    args += [] if change.get("no_legend") else ["--legend", legend]
    args += ["--band", change["band"]] if "band" in change else []
    args += ["--color", change["color"]] if "color" in change else []
    out = tmp_path / "world"
    run = cli(*args, "--out", out, timeout=60)
    print(f"{case}: {run.stderr.strip()}")
    assert_refused(run, words)
    assert not out.exists()


def square(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]]


def feature(color, *rings, kind="Polygon"):
    geometry = {"type": kind, "coordinates": list(rings) if kind == "Polygon" else [list(rings)]}
    return {"type": "Feature", "properties": {"color": color}, "geometry": geometry}


def polygons(*features, background="Meadow"):
    data = {"type": "FeatureCollection", "features": list(features)}
    if background is not None:
        data["background"] = background
    return data


# the benchmark color west of x = 200 m, but for a meadow lake (a hole) in its middle; meadow elsewhere
WEST_WITH_A_LAKE = polygons(feature("Bench", square(-50, -50, BOUNDARY, SIDE + 50), square(40, 140, 120, 260)))


def test_a_map_of_polygons_paints_each_feature_with_its_color_and_keeps_its_holes(inputs, tmp_path):
    path = tmp_path / "regions.geojson"
    path.write_text(json.dumps(WEST_WITH_A_LAKE))
    out = tmp_path / "world"
    run = cli("--palette", inputs["palette"], "--map", path, "--region", 0, 0, SIDE, SIDE, "--tile", 100,
              "--seed", 3, "--out", out, "--workers", 1, "--quiet")
    assert run.returncode == 0, run.stderr
    manifest = world.read_manifest(out)
    assert manifest["colors"] == ["Meadow", "Bench"]
    tiles = [engine.read_world_tile((out / t["file"]).read_bytes()) for t in manifest["tiles"]]
    xy = np.concatenate([t["positions"] for t in tiles])
    bush = np.concatenate([np.asarray(t["categories"])[t["category_index"]] == "Bush" for t in tiles])

    def count(x0, y0, x1, y1, of_bush):
        inside = (xy[:, 0] >= x0) & (xy[:, 0] < x1) & (xy[:, 1] >= y0) & (xy[:, 1] < y1) & (bush == of_bush)
        return inside.sum(), (x1 - x0) * (y1 - y0)

    # the benchmark color away from the lake and the boundary, the meadow east and in the lake's middle
    n, area = count(0, 300, 120, SIDE, False)
    assert abs(n / area / 0.1 - 1.0) < 0.1, n / area
    n, area = count(280, 0, SIDE, SIDE, True)
    assert abs(n / area / MEADOW_DENSITY - 1.0) < 0.25, n / area
    assert count(280, 0, SIDE, SIDE, False)[0] == 0
    lake, _ = count(70, 190, 90, 210, False)
    assert lake == 0, "the benchmark color grew in the lake"
    # a feature drawn over another paints over it: the lake as a feature of its own gives the same world
    path.write_text(json.dumps(polygons(feature("Bench", square(-50, -50, BOUNDARY, SIDE + 50)),
                                        feature("Meadow", square(40, 140, 120, 260)))))
    again = tmp_path / "again"
    run = cli("--palette", inputs["palette"], "--map", path, "--region", 0, 0, SIDE, SIDE, "--tile", 100,
              "--seed", 3, "--out", again, "--workers", 1, "--quiet")
    assert run.returncode == 0, run.stderr
    assert snapshot(again) == snapshot(out)


BAD_POLYGONS = [
    ("not a collection", {"type": "Feature"}, ["regions.geojson", "FeatureCollection"]),
    ("a point", polygons({"type": "Feature", "properties": {"color": "Bench"},
                          "geometry": {"type": "Point", "coordinates": [1, 2]}}),
     ["regions.geojson", "feature 1 is a Point", "Polygons or MultiPolygons"]),
    ("no color", polygons({"type": "Feature", "properties": {}, "geometry": feature("x", square(0, 0, 9, 9))[
        "geometry"]}), ["feature 1's \"color\"", "None", "Bench, Meadow"]),
    ("unknown color", polygons(feature("Orchard", square(0, 0, 9, 9))), ["'Orchard'", "palette does not have"]),
    ("unknown background", polygons(feature("Bench", square(0, 0, 9, 9)), background="Desert"),
     ["the background", "'Desert'"]),
    ("nothing behind", polygons(feature("Bench", square(0, 0, 100, 100)), background=None),
     ["the point 100.5 0.5 lies in no feature", '"background"']),
    ("short ring", polygons(feature("Bench", [[0, 0], [9, 0], [0, 0]])), ["feature 1", "at least 4 positions"]),
    ("nan position", polygons(feature("Bench", [[0, 0], [float("nan"), 0], [9, 9], [0, 0]])),
     ["feature 1", "finite numbers"]),
    ("multipolygon of junk", polygons({"type": "Feature", "properties": {"color": "Bench"},
                                       "geometry": {"type": "MultiPolygon", "coordinates": [["a"]]}}),
     ["feature 1", "at least 4 positions"]),
]


@pytest.mark.parametrize("case, data, words", BAD_POLYGONS, ids=[c[0] for c in BAD_POLYGONS])
def test_bad_polygons_are_refused_with_one_line_before_any_tile(inputs, tmp_path, case, data, words):
    path = tmp_path / "regions.geojson"
    path.write_text(json.dumps(data))
    out = tmp_path / "world"
    run = cli("--palette", inputs["palette"], "--map", path, "--region", 0, 0, SIDE, SIDE, "--out", out, "--quiet",
              timeout=60)
    print(f"{case}: {run.stderr.strip()}")
    assert_refused(run, words)
    assert not out.exists()


def test_polygons_take_no_legend(inputs, tmp_path):
    path = tmp_path / "regions.geojson"
    path.write_text(json.dumps(WEST_WITH_A_LAKE))
    run = cli("--palette", inputs["palette"], "--map", path, "--legend", inputs["legend"], "--region", 0, 0, SIDE,
              SIDE, "--out", tmp_path / "world", "--quiet", timeout=60)
    assert_refused(run, ["--legend", "name their colors themselves", "take no legend"])
