"""A real place imported inside Blender, from ``shared/data/real`` beside the project (skipped with a message where
absent).

Through the engine facade: Andorra's OpenStreetMap layers and SRTM terrain come back in local metres with every
building, road and place of the source; a second import given the first one's origin lines up with it; the engine's
result dicts carry the keys and dtypes the stub declares; bad files raise the engine's exceptions with what is wrong.

Through File › Import › WorldPaint Place (the operator, headless): Andorra and Bayreuth become a terrain mesh of the
engine's grid, a building instance per building of the source in a category per type, each instance its footprint's
size and heading, and road curves as long as the engine's roads; a second import lines up with the first, also after
save and reload; the Luquillo inventory brings its 2,595 trees; bad files, a cancel and a CRS it cannot place report
an error and leave the scene exactly as it was; one undo removes an import; and Learn Color learns a Bayreuth village
from the imported clouds and curves. ``-s`` prints the import times and counts.
"""

import json
import math
import pathlib
import time
from collections import Counter

import bpy
import numpy as np
import pytest
from scene_kit import select_only
from test_engine_stub import check
from worldpaint.bridge import curves, engine, engine_place, place, snap
from worldpaint.bridge.geometry import spline_control_points
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects, point_cloud_stretch
from worldpaint.builtin.prototypes import BUILDING_SHAPES
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
    place = engine_place.import_place([str(p) for p in layers], str(dem), progress=lambda f, stage: stages.append(stage)
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
    first = engine_place.import_place([layers[0], layers[1]])
    roads = engine_place.import_place([layers[1]], origin=first.origin)
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
        engine_place.import_place([write(tmp_path / "text.geojson", "hello")])
    with pytest.raises(engine.FileFormatError, match="an empty layer"):
        engine_place.import_place([write(tmp_path / "empty.geojson", '{"type": "FeatureCollection", "features": []}')])
    utm = '{"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": "EPSG:32632"}}, "features": []}'
    with pytest.raises(engine.FileFormatError, match="a CRS it cannot place"):
        engine_place.import_place([write(tmp_path / "utm.geojson", utm)])
    rows = "\n".join(" ".join("-32768" if (r + c) % 5 == 0 else "400" for c in range(100)) for r in range(100))
    holes = write(tmp_path / "holes.asc", "ncols 100\nnrows 100\nxllcorner 11\nyllcorner 49\ncellsize 0.001\n"
                                          "NODATA_value -32768\n" + rows + "\n")
    with pytest.raises(engine.InputError, match=r"no data in 20\.\d % of its samples under the place"):
        engine_place.import_place([layer], holes)
    with pytest.raises(TypeError):
        _engine.import_place(layer)  # the engine takes a list of paths, not one path's characters
    assert engine_place.import_place(layer).roads.kind == engine_place.import_place([layer]).roads.kind == ("track",)


# --- through the operator -------------------------------------------------------------------------------------------

def operator_import(layers=(), dem=None, inventory=None, **settings):
    """Runs File › Import › WorldPaint Place headless; its seconds."""
    start = time.perf_counter()
    result = bpy.ops.worldpaint.import_place(layers=";".join(str(p) for p in layers), elevation=str(dem or ""),
                                             inventory=str(inventory or ""), **settings)
    assert result == {'FINISHED'}
    return time.perf_counter() - start


def building_clouds(scene):
    names = set(place.BUILDING_CATEGORIES.values())
    return {c: o for c, o in point_cloud_objects(scene).items() if c in names}


def road_lines(scene):
    names = {name for name, _ in place.ROAD_CATEGORIES.values()}
    return [spline_control_points(o, s) for c, o in curves.structure_objects(scene).items() if c in names
            for s in o.data.splines]


def length(lines):
    return sum(float(np.linalg.norm(np.diff(np.asarray(p)[:, :2], axis=0), axis=1).sum()) for p in lines)


def building_instances(scene):
    """(XYZ, X axis, Y axis, Z axis) of every evaluated building instance, by cloud category."""
    clouds = {o.name: c for c, o in building_clouds(scene).items()}
    out: dict[str, list] = {}
    for instance in bpy.context.evaluated_depsgraph_get().object_instances:
        if instance.is_instance and instance.parent.original.name in clouds:
            m = np.array(instance.matrix_world)
            out.setdefault(clouds[instance.parent.original.name], []).append((m[:3, 3], m[:3, 0], m[:3, 1], m[:3, 2]))
    return out


@pytest.mark.parametrize("stem", ["andorra", "north_bayreuth"])
def test_a_real_place_comes_in_through_the_operator_as_terrain_buildings_and_roads(stem):
    layers, dem = real_files(stem)
    seconds = operator_import(layers, dem)
    scene = bpy.context.scene
    source = engine_place.import_place([str(p) for p in layers], str(dem))  # the same files: the same frame
    b = source.buildings
    n_buildings = source_count(layers[0], "building")
    clouds = building_clouds(scene)
    counts = {c: len(o.data.vertices) for c, o in clouds.items()}
    road_length = length(road_lines(scene))
    engine_road_length = length([p for p in source.roads.points if len(p) >= 2])
    print(f"{stem}: imported through the operator in {seconds:.1f} s: {sum(counts.values())} building instances "
          f"({counts}), {len(road_lines(scene))} road curves {road_length / 1000:.1f} km (engine "
          f"{engine_road_length / 1000:.1f} km)")

    # every building of the source, each type a category of its own
    assert sum(counts.values()) == len(b.type) == n_buildings
    expected = Counter(place.BUILDING_CATEGORIES[kind] for kind in b.type)
    assert counts == dict(expected)
    kinds = {c.name: c.kind for c in scene.worldpaint.categories}
    assert all(kinds[name] == "distribution" for name in expected)
    assert {"Building", "Church"} <= set(expected)

    # the terrain mesh is the engine's grid, picked as the scene's terrain
    terrain_obj = scene.worldpaint.terrain
    assert terrain_obj is place.place_terrain(scene) and terrain_obj is not None
    co = np.empty(len(terrain_obj.data.vertices) * 3, dtype=np.float32)
    terrain_obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    grid = source.terrain
    ny, nx = grid.heights.shape
    np.testing.assert_allclose(co[:, :2].min(axis=0), grid.origin, atol=0.01)
    np.testing.assert_allclose(co[:, :2].max(axis=0), np.add(grid.origin, ((nx - 1) * grid.cell, (ny - 1) * grid.cell)),
                               atol=0.01)
    np.testing.assert_allclose(co[:, 2], grid.heights.ravel(), atol=1e-3)

    # roads as long as the engine's, within 1 %
    assert road_length == pytest.approx(engine_road_length, rel=0.01)

    # each building instance stands at its footprint's centroid on the terrain, along its long side, the footprint's
    # length by width, the type's height
    shown = building_instances(scene)
    assert {c: len(v) for c, v in shown.items()} == counts, "one instance per building, instanced by Geometry Nodes"
    for category, rows in shown.items():
        kind = next(k for k, name in place.BUILDING_CATEGORIES.items() if name == category)
        model_length, model_width = BUILDING_SHAPES[kind][:2]
        mine = np.flatnonzero([t == kind for t in b.type])
        where = np.array([r[0] for r in rows])
        for k in mine:
            i = int(np.argmin(np.linalg.norm(where[:, :2] - b.centroid[k], axis=1)))
            at, x_axis, y_axis, z_axis = rows[i]
            assert np.linalg.norm(at[:2] - b.centroid[k]) < 1e-3
            assert np.linalg.norm(x_axis) * model_length == pytest.approx(b.size[k, 0], rel=1e-4)
            assert np.linalg.norm(y_axis) * model_width == pytest.approx(b.size[k, 1], rel=1e-4)
            assert np.linalg.norm(z_axis) == pytest.approx(1.0, rel=1e-4)
            turn = (math.atan2(x_axis[1], x_axis[0]) - b.orientation[k]) % math.pi
            assert min(turn, math.pi - turn) < 1e-4
    # standing on the terrain mesh (its triangles: the engine's bilinear grid differs by up to a few metres on
    # Andorra's slopes, 68 m between nodes); the few beyond the elevation model at the height of its nearest edge
    co = np.concatenate([point_cloud_arrays(o)[0] for o in clouds.values()])
    z = snap.surface(terrain_obj).heights(co[:, :2])
    on = np.isfinite(z)
    np.testing.assert_allclose(co[on, 2], z[on], atol=0.01)
    (x0, y0), (x1, y1) = place.grid_heightfield(grid).bbox()
    edge = np.column_stack([np.clip(co[~on, 0], x0, x1), np.clip(co[~on, 1], y0, y1)])
    np.testing.assert_allclose(co[~on, 2], place.grid_heightfield(grid).heights_at(edge), atol=0.01)
    print(f"{stem}: {(~on).sum()} buildings beyond the elevation model, at the height of its edge")

    # the frame and the files, kept on the place's collection
    collection = place.place_collection(scene, create=False)
    assert place.place_origin(scene) == source.origin
    assert collection["wp_projection"] == source.projection and collection["wp_cell"] == grid.cell
    assert place.place_sources(collection) == [p.name for p in layers] + [dem.name]


def test_a_second_import_lines_up_with_the_place_also_after_save_and_reload(tmp_path):
    layers, dem = real_files("andorra")
    buildings, roads, areas = (str(p) for p in layers[:3])
    operator_import([buildings, roads], dem)
    scene = bpy.context.scene
    origin = place.place_origin(scene)
    first = point_cloud_arrays(point_cloud_objects(scene)["Building"])[0].copy()
    path = str(tmp_path / "andorra.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=path)
    scene = bpy.context.scene
    assert place.place_origin(scene) == origin, "the frame is saved with the file"

    # the areas, with the buildings again: the frame is the place's, not the new files' centre
    operator_import([areas, buildings])
    assert place.place_origin(scene) == origin
    clouds = point_cloud_objects(scene)
    again = engine_place.import_place([areas, buildings], origin=origin)
    alone = engine_place.import_place([areas, buildings])
    shift = np.linalg.norm(np.subtract(alone.buildings.centroid, again.buildings.centroid), axis=1).min()
    print(f"the second import's own centre lies {shift:.0f} m from the place's frame; the place's is used")
    assert shift > 100.0, "without the place's origin the buildings would not line up"
    # the buildings of both imports are at exactly the same XY: kept once
    after = point_cloud_arrays(clouds["Building"])[0]
    np.testing.assert_array_equal(after, first)
    mine = np.array([t == "other" for t in again.buildings.type])
    np.testing.assert_array_equal(np.sort(after[:, :2].astype(np.float32), axis=0),
                                  np.sort(again.buildings.centroid[mine].astype(np.float32), axis=0))
    # the areas came in, in the same frame: the forest's rings are the engine's
    forest = curves.structure_objects(scene)["Forest"]
    rings = [r for k, rings in enumerate(again.areas.rings) if again.areas.kind[k] == "forest" for r in rings]
    assert len(forest.data.splines) == len(rings)
    np.testing.assert_allclose(spline_control_points(forest, forest.data.splines[0])[:, :2], rings[0], atol=1e-3)
    assert place.place_terrain(scene) is scene.worldpaint.terrain, "the terrain stays the first import's"
    assert place.place_sources(place.place_collection(scene)) == [layers[0].name, layers[1].name, dem.name,
                                                                   layers[2].name]


def test_the_luquillo_inventory_brings_its_trees_by_species():
    inventory = REAL / "forest" / "luquillo_tree6_1ha.csv"
    if not inventory.is_file():
        pytest.skip(f"{inventory} not found (the real data lives beside the project, in shared/data/real)")
    seconds = operator_import(inventory=inventory)
    scene = bpy.context.scene
    trees = engine_place.import_place([], None, str(inventory)).trees
    clouds = point_cloud_objects(scene)
    counts = {c: len(o.data.vertices) for c, o in clouds.items()}
    print(f"Luquillo: {sum(counts.values())} trees in {len(counts)} categories in {seconds:.1f} s: {counts}")
    assert sum(counts.values()) == len(trees.kind) == 2595
    by_species = Counter(trees.kind)
    common = [name for name, _ in sorted(by_species.items(), key=lambda item: (-item[1], item[0]))[:12]]
    assert set(counts) == set(common) | {place.OTHER_TREES}
    assert all(counts[name] == by_species[name] for name in common)
    assert counts[place.OTHER_TREES] == sum(n for name, n in by_species.items() if name not in common) > 0
    # a tree's scale: the square root of its dbh over the median dbh
    k = int(np.nanargmax(trees.size))
    co, _, scale, _ = point_cloud_arrays(clouds[place.tree_categories(trees.kind, 12)[k]])
    i = int(np.argmin(np.linalg.norm(co[:, :2] - trees.position[k], axis=1)))
    assert scale[i] == pytest.approx(min(math.sqrt(trees.size[k] / np.nanmedian(trees.size)), 3.0), rel=1e-5)
    assert place.place_origin(scene) is None and place.place_terrain(scene) is None, "local metres, no terrain"
    shown = sum(1 for i in bpy.context.evaluated_depsgraph_get().object_instances if i.is_instance)
    assert shown == 2595


def scene_state():
    """What an import that fails must leave as it was: every object and collection with what it holds, the
    categories, the place's properties, and the data blocks."""
    scene = bpy.context.scene
    collection = place.place_collection(scene, create=False)
    return (
        sorted((o.name, o.type, len(o.data.vertices) if o.type == 'MESH' else len(o.data.splines) if o.type == 'CURVE'
                else 0) for o in bpy.data.objects),
        sorted((c.name, tuple(sorted(o.name for o in c.objects))) for c in bpy.data.collections),
        [(c.name, c.kind, c.priority) for c in scene.worldpaint.categories],
        None if collection is None else dict(collection.items()),
        scene.worldpaint.terrain.name if scene.worldpaint.terrain else None,
        len(bpy.data.meshes), len(bpy.data.curves), len(bpy.data.materials), len(bpy.data.node_groups),
    )


def test_bad_files_report_an_error_and_leave_the_scene_as_it_was(tmp_path):
    layer, dem, _ = small_place(tmp_path)
    operator_import([layer], dem, cell=25.0, margin=100.0)
    before = scene_state()
    assert before[0], "the place was built"
    holes = "\n".join(" ".join("-32768" if (r + c) % 5 == 0 else "400" for c in range(100)) for r in range(100))
    utm = ('{"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": "EPSG:32632"}}, '
           '"features": []}')
    bad = [
        ({"layers": write(tmp_path / "text.geojson", "hello")}, "not GeoJSON"),
        ({"layers": write(tmp_path / "empty.geojson", '{"type": "FeatureCollection", "features": []}')},
         "an empty layer"),
        ({"layers": write(tmp_path / "utm.geojson", utm)}, "a CRS it cannot place"),
        ({"layers": layer, "elevation": write(tmp_path / "holes.asc", "ncols 100\nnrows 100\nxllcorner 11\n"
                                              "yllcorner 49\ncellsize 0.001\nNODATA_value -32768\n" + holes + "\n")},
         r"no data in 20\.\d % of its samples under the place"),
        ({"layers": str(tmp_path / "nowhere.geojson")}, "cannot read it"),
        ({"filepath": dem, "elevation": dem}, "A place has one elevation model: 2 were given"),
        ({}, "Choose the place's files"),
        ({"layers": layer, "time_limit": 1e-9}, "stopped at the time limit"),
    ]
    ring = [[1.0, 42.0], [1.001, 42.0], [1.001, 42.001], [1.0, 42.0]]  # 10° from the place: no one frame
    far = {"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"building": "yes"},
                                                      "geometry": {"type": "Polygon", "coordinates": [ring]}}]}
    bad.append(({"layers": write(tmp_path / "far.geojson", json.dumps(far))}, "cannot line up with it"))
    for settings, message in bad:
        with pytest.raises(RuntimeError, match=message):
            bpy.ops.worldpaint.import_place(**settings)
        assert scene_state() == before, f"{message}: the scene changed"
    # a category of the scene that the place would make another kind of
    forest = bpy.context.scene.worldpaint.categories.add()
    forest.name, forest.kind = "Meadow", "distribution"
    before = scene_state()
    with pytest.raises(RuntimeError, match="The scene's category 'Meadow' is a distribution"):
        bpy.ops.worldpaint.import_place(layers=layer)
    assert scene_state() == before


def test_one_undo_removes_an_import(tmp_path):
    layer, dem, trees = small_place(tmp_path)
    before = scene_state()
    bpy.ops.ed.undo_push(message="before the import")
    operator_import([layer], dem, trees, cell=25.0, margin=100.0)
    bpy.ops.ed.undo_push(message="Import WorldPaint Place")  # what the UI does after an UNDO operator
    assert scene_state() != before
    bpy.ops.ed.undo()
    assert scene_state() == before


def test_learn_color_learns_a_bayreuth_village_from_the_imported_place():
    layers, dem = real_files("north_bayreuth")
    operator_import(layers, dem)
    scene = bpy.context.scene
    villages = engine_place.import_place([str(layers[3])], origin=place.place_origin(scene)).places
    centre = villages.position[villages.name.index("Neudrossenfeld")]
    low, high = centre - 400.0, centre + 400.0
    clouds = building_clouds(scene)
    road_names = {name for name, _ in place.ROAD_CATEGORIES.values()}
    roads = [o for c, o in curves.structure_objects(scene).items() if c in road_names]
    select_only([*clouds.values(), *roads])
    assert bpy.ops.worldpaint.learn_color(name="Neudrossenfeld", region_mode='RECT', rect_min=tuple(low),
                                          rect_max=tuple(high)) == {'FINISHED'}
    color = scene.worldpaint.palette["Neudrossenfeld"]
    learned = {c.name: (c.kind, c.count) for c in engine.color_summary(color.json).categories}
    inside = {}
    for category, obj in clouds.items():
        xy = point_cloud_arrays(obj)[0][:, :2]
        n = int(np.all((xy >= low) & (xy <= high), axis=1).sum())
        if n:
            inside[category] = n
    print(f"Neudrossenfeld, 800 m square: {learned}; {color.fidelity_line()}")
    assert {name: count for name, (kind, count) in learned.items() if kind == "distribution"} == inside
    assert inside["Building"] > 300 and "Church" in inside
    assert {name for name, (kind, _) in learned.items() if kind == "graph"} >= {"Residential street", "Minor road"}


def test_a_building_cloud_keeps_its_footprints_through_an_edit():
    layers, dem = real_files("andorra")
    operator_import(layers[:1], dem)
    cloud = point_cloud_objects(bpy.context.scene)["Building"]
    stretch = point_cloud_stretch(cloud)
    assert not np.allclose(stretch, 1.0)
    co = point_cloud_arrays(cloud)[0]
    # Convert to Objects makes each church its footprint's length by width
    sizes = engine_place.import_place([str(layers[0])], str(dem)).buildings
    assert bpy.ops.worldpaint.convert_to_objects(category="Church") == {'FINISHED'}
    made = [o for o in bpy.context.scene.objects if o.name.startswith("Church.")]
    assert len(made) == Counter(sizes.type)["church"] == 5
    length, width = BUILDING_SHAPES["church"][:2]
    expected = sorted(tuple(sizes.size[k]) for k, t in enumerate(sizes.type) if t == "church")
    np.testing.assert_allclose(sorted((o.scale.x * length, o.scale.y * width) for o in made), expected, rtol=1e-5)
    # Clear Region removes the points of a region and writes the cloud again: the others keep their shape
    low, middle = co[:, :2].min(axis=0) - 1.0, np.median(co[:, :2], axis=0)
    keep = ~np.all(co[:, :2] < middle, axis=1)
    assert bpy.ops.worldpaint.clear_region(region_mode='RECT', rect_min=tuple(low), rect_max=tuple(middle)) \
        == {'FINISHED'}
    after = point_cloud_stretch(cloud)
    assert len(after) == keep.sum() < len(co)
    np.testing.assert_array_equal(after, stretch[keep])
