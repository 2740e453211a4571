"""A real place imported through the add-on's engine facade, inside Blender: Andorra's OpenStreetMap layers and SRTM
terrain (from ``shared/data/real`` beside the project; skipped with a message where absent) come back in local metres
with every building, road and place of the source; a second import given the first one's origin lines up with it;
the engine's result dicts carry the keys and dtypes the stub declares; bad files raise the engine's exceptions with
what is wrong."""

import json
import math
import pathlib

import numpy as np
import pytest
from test_engine_stub import check
from worldpaint.bridge import engine
from worldpaint_engine import _engine

REAL = pathlib.Path(__file__).resolve().parents[1].parent / "shared" / "data" / "real"
LAYERS = ["buildings", "roads", "areas", "places"]


def real_files(stem):
    files = [REAL / "villages" / f"{stem}_{name}.geojson" for name in LAYERS] + [REAL / "terrain" / f"{stem}_srtm3.asc"]
    missing = [f for f in files if not f.is_file()]
    if missing:
        pytest.skip(f"{missing[0]} not found (the real data lives beside the project, in shared/data/real)")
    return files[:-1], files[-1]


def source_count(path, key):
    features = json.loads(path.read_text(encoding="utf-8"))["features"]
    return sum(1 for f in features if key in (f.get("properties") or {}))


def test_andorra_comes_in_with_every_building_road_and_place():
    layers, dem = real_files("andorra")
    stages = []
    place = engine.import_place([str(p) for p in layers], str(dem), progress=lambda f, stage: stages.append(stage)
                                or True)
    assert "reading map layers" in stages and "resampling the terrain" in stages
    assert len(place.buildings.type) == source_count(layers[0], "building") == 292
    assert len(place.roads.kind) == source_count(layers[1], "highway") == 1613
    assert len(place.places.kind) == 68
    lon, lat = place.origin
    assert 1.4 < lon < 1.8 and 42.4 < lat < 42.7
    assert place.projection.startswith("+proj=tmerc")
    assert place.layers == tuple(str(p) for p in layers) and place.elevation == str(dem)
    terrain = place.terrain
    ny, nx = terrain.heights.shape
    print(f"Andorra: {len(place.buildings.type)} buildings, {len(place.roads.kind)} roads, {len(place.areas.kind)} "
          f"areas, {len(place.places.kind)} places; terrain {nx} x {ny} nodes of {terrain.cell:.1f} m, heights "
          f"{terrain.heights.min():.0f}..{terrain.heights.max():.0f} m; report {place.report}")
    # Andorra's valleys lie between 800 and 2,950 m
    assert 800.0 < terrain.heights.min() and terrain.heights.max() < 2950.0
    # every building stands on the terrain, with a footprint that holds its centroid's box
    assert np.all(np.isfinite(place.buildings.height))
    for centroid, rings, size in zip(place.buildings.centroid, place.buildings.footprints, place.buildings.size,
                                     strict=True):
        lo, hi = rings[0].min(axis=0), rings[0].max(axis=0)
        assert np.all(lo <= centroid + 1e-6) and np.all(centroid <= hi + 1e-6)
        assert size[0] >= size[1] > 0.0
    assert {"church"} <= set(place.buildings.type)
    # roads are draped on the terrain: their heights within the terrain's
    heights = np.concatenate(place.roads.heights)
    assert np.nanmin(heights) >= terrain.heights.min() - 1e-3 and np.nanmax(heights) <= terrain.heights.max() + 1e-3
    # a road's length in metres matches its length on the sphere within 1 %
    with open(layers[1], encoding="utf-8") as f:
        first = json.load(f)["features"][0]["geometry"]["coordinates"]
    on_sphere = sum(haversine(a, b) for a, b in zip(first, first[1:], strict=False))
    local = np.sum(np.linalg.norm(np.diff(place.roads.points[0], axis=0), axis=1))
    assert local == pytest.approx(on_sphere, rel=0.01)


def haversine(a, b):
    (l1, p1), (l2, p2) = np.radians(a), np.radians(b)
    h = math.sin((p2 - p1) / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin((l2 - l1) / 2) ** 2
    return 2.0 * 6_371_008.8 * math.asin(math.sqrt(h))


def test_a_second_import_with_the_first_origin_lines_up():
    layers, _ = real_files("andorra")
    first = engine.import_place([layers[0], layers[1]])
    roads = engine.import_place([layers[1]], origin=first.origin)
    assert roads.origin == first.origin
    for a, b in zip(first.roads.points, roads.roads.points, strict=True):
        np.testing.assert_array_equal(a, b)


def write(path, text):
    path.write_text(text, encoding="utf-8")
    return str(path)


def small_place(tmp_path):
    """A building, a road, a stream, a meadow, a hamlet on a tilted grid, and two trees, written here."""
    ring = [[11.049, 49.049], [11.051, 49.049], [11.051, 49.051], [11.049, 49.051], [11.049, 49.049]]
    features = [
        {"type": "Feature", "properties": {"building": "barn"}, "geometry": {"type": "Polygon", "coordinates": [ring]}},
        {"type": "Feature", "properties": {"highway": "track", "name": "Feldweg"},
         "geometry": {"type": "LineString", "coordinates": [[11.04, 49.05], [11.06, 49.05]]}},
        {"type": "Feature", "properties": {"waterway": "stream"},
         "geometry": {"type": "LineString", "coordinates": [[11.05, 49.04], [11.05, 49.06]]}},
        {"type": "Feature", "properties": {"landuse": "meadow"},
         "geometry": {"type": "Polygon", "coordinates": [ring]}},
        {"type": "Feature", "properties": {"place": "hamlet", "name": "Au"},
         "geometry": {"type": "Point", "coordinates": [11.05, 49.05]}},
    ]
    layer = write(tmp_path / "place.geojson", json.dumps({"type": "FeatureCollection", "features": features}))
    n = 100
    rows = [" ".join(f"{400.0 + 3.0 * c + 2.0 * r:.1f}" for c in range(n)) for r in range(n)]
    dem = write(tmp_path / "dem.asc", f"ncols {n}\nnrows {n}\nxllcorner 11\nyllcorner 49\ncellsize 0.001\n"
                                      f"NODATA_value -32768\n" + "\n".join(rows) + "\n")
    trees = write(tmp_path / "trees.csv", "lon,lat,species,dbh\n11.05,49.05,oak,0.4\n11.051,49.05,beech,\n")
    return layer, dem, trees


def test_the_result_dicts_carry_the_keys_and_dtypes_the_stub_declares(tmp_path):
    layer, dem, trees = small_place(tmp_path)
    d = _engine.import_place([layer], dem, trees, cell=25.0, margin=100.0)
    check(d, "PlaceDict")
    for key, name in [("frame", "PlaceFrameDict"), ("sources", "PlaceSourcesDict"), ("terrain", "TerrainGrid"),
                      ("buildings", "PlaceBuildingsDict"), ("roads", "PlaceRoadsDict"),
                      ("waterways", "PlaceWaterwaysDict"), ("areas", "PlaceAreasDict"), ("places", "PlacePointsDict"),
                      ("trees", "PlaceTreesDict"), ("report", "PlaceReportDict")]:
        check(d[key], name)
    assert d["terrain"]["heights"].dtype == np.float32 and d["terrain"]["cell"] == 25.0
    assert d["buildings"]["type"] == ["barn"] and d["roads"]["kind"] == ["track"] and d["roads"]["name"] == ["Feldweg"]
    assert d["waterways"]["kind"] == ["stream"] and d["areas"]["kind"] == ["meadow"]
    assert d["places"]["name"] == ["Au"] and d["trees"]["species"] == ["oak", "beech"]
    assert np.isnan(d["trees"]["size"][1]) and d["trees"]["size"][0] == 0.4
    # the barn is 0.002° square: 146 m east–west by 222 m north–south at 49.05° N, its long side north
    length, width = d["buildings"]["size"][0]
    assert length == pytest.approx(222.4, abs=0.5) and width == pytest.approx(146.0, abs=0.5)
    assert d["buildings"]["orientation"][0] == pytest.approx(math.pi / 2, abs=0.01)


def test_bad_files_raise_the_engines_errors_with_what_is_wrong(tmp_path):
    layer, dem, _ = small_place(tmp_path)
    with pytest.raises(engine.FileFormatError, match="not GeoJSON"):
        engine.import_place([write(tmp_path / "text.geojson", "hello")])
    with pytest.raises(engine.FileFormatError, match="an empty layer"):
        engine.import_place([write(tmp_path / "empty.geojson", '{"type": "FeatureCollection", "features": []}')])
    utm = '{"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": "EPSG:32632"}}, "features": []}'
    with pytest.raises(engine.FileFormatError, match="a CRS it cannot place"):
        engine.import_place([write(tmp_path / "utm.geojson", utm)])
    rows = "\n".join(" ".join("-32768" if (r + c) % 5 == 0 else "400" for c in range(100)) for r in range(100))
    holes = write(tmp_path / "holes.asc", "ncols 100\nnrows 100\nxllcorner 11\nyllcorner 49\ncellsize 0.001\n"
                                          "NODATA_value -32768\n" + rows + "\n")
    with pytest.raises(engine.InputError, match=r"no data in 20\.\d % of its samples under the place"):
        engine.import_place([layer], holes)
    with pytest.raises(TypeError):
        _engine.import_place(layer)  # the engine takes a list of paths, not one path's characters
    assert engine.import_place(layer).roads.kind == engine.import_place([layer]).roads.kind == ("track",)
