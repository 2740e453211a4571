"""Villages grown on a hill through the Village panel's operators: houses with walls, roofs, doors and windows stand
beside the roads, never on them; the roads lie on the terrain; the interest maps color the terrain; undo, save and
reload keep what a user expects."""

import json

import bpy
import numpy as np
import pytest
import worldpaint_engine as engine
from scene_kit import grid_terrain, poly_curve
from worldpaint.bridge.geometry import spline_control_points as spline_points

SIZE = 400.0  # the hill's terrain, metres across
CELL = 2.0
CENTER = (200.0, 200.0)
RADIUS = 150.0  # the village region: a circle in the middle of the terrain
REACH = 12.0  # a house's front wall is at most this far beyond the road's edge
MATERIALS = ["Wall", "Roof", "Door", "Window", "Foundation"]


def hill_height(x, y):
    """A round hill with a shoulder, on ground rising gently to the east (m)."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    hill = 30.0 * np.exp(-((x - 210.0) ** 2 + (y - 230.0) ** 2) / (2.0 * 70.0**2))
    shoulder = 8.0 * np.exp(-((x - 120.0) ** 2 + (y - 120.0) ** 2) / (2.0 * 50.0**2))
    return hill + shoulder + 0.02 * x + 1.5 * np.sin(y / 37.0)


def hill_scene():
    """The hill as the WorldPaint terrain and a closed curve "Region" around the village's place."""
    n = int(SIZE / CELL) + 1
    x, y = np.meshgrid(CELL * np.arange(n), CELL * np.arange(n))
    terrain_obj = grid_terrain("Terrain", (0.0, 0.0), CELL, hill_height(x, y))
    bpy.context.scene.worldpaint.terrain = terrain_obj
    a = np.linspace(0.0, 2.0 * np.pi, 64, endpoint=False)
    xy = np.column_stack([CENTER[0] + RADIUS * np.cos(a), CENTER[1] + RADIUS * np.sin(a)])
    region = poly_curve("Region", xy, cyclic=True)
    bpy.context.scene.worldpaint.village.region = region
    return terrain_obj, region


def village_collection():
    return bpy.context.scene.worldpaint.village.collection


def houses():
    return sorted((o for o in village_collection().objects if o.get("wp_village") == "house"), key=lambda o: o.name)


def road_object():
    return next(o for o in village_collection().objects if o.get("wp_village") == "roads")


def world_vertices(obj):
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    matrix = np.array(obj.matrix_world)
    return co.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]


def face_materials(mesh):
    materials = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("material_index", materials)
    return materials


def footprint(obj):
    """The house's footprint (4, 2): the XY corners of its walls (the roof's eaves reach further out)."""
    co = world_vertices(obj)
    walls = face_materials(obj.data) == 0
    used = np.unique(np.concatenate([list(p.vertices) for p, wall in zip(obj.data.polygons, walls, strict=True)
                                     if wall]))
    xy = co[used, :2]
    # the wall corners as the convex hull of the wall vertices (a quadrilateral, counter-clockwise)
    order = np.lexsort((xy[:, 1], xy[:, 0]))
    pts = [tuple(p) for p in xy[order]]

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    hull = []
    for sweep in (pts, pts[::-1]):
        chain = []
        for p in sweep:
            while len(chain) >= 2 and cross(chain[-2], chain[-1], p) <= 1e-3:
                chain.pop()
            chain.append(p)
        hull += chain[:-1]
    return np.array(hull)


def densify(polyline, step, closed=False):
    """Points every ``step`` metres along a polyline (N, 2)."""
    pts = np.vstack([polyline, polyline[:1]]) if closed else polyline
    out = [pts[:1]]
    for a, b in zip(pts[:-1], pts[1:], strict=True):
        n = max(int(np.ceil(np.linalg.norm(b - a) / step)), 1)
        out.append(a + (b - a) * (np.arange(1, n + 1)[:, None] / n))
    return np.concatenate(out)


def distance_to_polylines(xy, polylines):
    """Distance from each point (N, 2) to the nearest segment of the polylines."""
    starts = np.concatenate([p[:-1] for p in polylines])
    ends = np.concatenate([p[1:] for p in polylines])
    d = ends - starts
    length2 = np.maximum((d * d).sum(axis=1), 1e-12)
    t = np.clip(((xy[:, None, :] - starts[None]) * d[None]).sum(axis=2) / length2, 0.0, 1.0)
    nearest = starts[None] + t[..., None] * d[None]
    return np.sqrt(((xy[:, None, :] - nearest) ** 2).sum(axis=2)).min(axis=1)


def polygon_contains(polygon, xy):
    return engine.region_contains({"shape": "polygon", "points": polygon.tolist()}, np.ascontiguousarray(xy))


def scenario_rows():
    return [(e.kind, e.village_type if e.kind == 'VILLAGE_TYPE' else e.building, e.count)
            for e in bpy.context.scene.worldpaint.village.events]


def village_report():
    return json.loads(village_collection()["wp_village_report"])


def snapshot():
    settings = bpy.context.scene.worldpaint
    return (len(bpy.data.objects), len(bpy.data.collections), len(bpy.data.meshes), len(bpy.data.curves),
            settings.village.collection, settings.village.report, len(settings.village.events))


@pytest.fixture(scope="module")
def grown(tmp_path_factory):
    """A farming hamlet grown on the hill (seed 3, parcels as curves), saved; tests open the file."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    hill_scene()
    settings = bpy.context.scene.worldpaint.village
    settings.parcels_as_curves = True
    assert bpy.ops.worldpaint.load_village_preset(preset="farming_hamlet") == {'FINISHED'}
    assert bpy.ops.worldpaint.generate_village(seed=3) == {'FINISHED'}
    path = str(tmp_path_factory.mktemp("village") / "hamlet.blend")
    saved = {"houses": [(o.name, o["wp_building"], tuple(o.matrix_world.translation)) for o in houses()],
             "events": scenario_rows(), "report": settings.report}
    bpy.ops.wm.save_as_mainfile(filepath=path)
    return path, saved


def open_grown(grown):
    bpy.ops.wm.open_mainfile(filepath=grown[0])
    return grown[1]


def test_a_preset_fills_the_scenario_list_which_edits_in_order():
    settings = bpy.context.scene.worldpaint.village
    assert bpy.ops.worldpaint.load_village_preset(preset="fortified_village") == {'FINISHED'}
    expected = json.loads(engine.scenario_presets())["presets"]["fortified_village"]["events"]
    assert scenario_rows() == [('VILLAGE_TYPE', e["village_type"], 1) if e["event"] == "change_village_type"
                               else ('GENERATE', e["building"], e["count"]) for e in expected]
    assert scenario_rows()[:4] == [('VILLAGE_TYPE', "farming", 1), ('GENERATE', "church", 1),
                                   ('GENERATE', "farm", 10), ('VILLAGE_TYPE', "defensive", 1)], "Fig. 3.4's order"
    assert ('GENERATE', "castle", 1) in scenario_rows()

    assert bpy.ops.worldpaint.load_village_preset(preset="highland_hamlet") == {'FINISHED'}
    assert scenario_rows()[0] == ('VILLAGE_TYPE', "highland", 1), "a preset replaces the list"
    n = len(settings.events)
    settings.active_event_index = 1
    assert bpy.ops.worldpaint.add_village_event(kind='GENERATE', name="villa", count=2) == {'FINISHED'}
    assert scenario_rows()[2] == ('GENERATE', "villa", 2) and settings.active_event_index == 2, "after the active one"
    assert bpy.ops.worldpaint.move_village_event(direction='UP') == {'FINISHED'}
    assert scenario_rows()[1] == ('GENERATE', "villa", 2)
    assert bpy.ops.worldpaint.remove_village_event() == {'FINISHED'}
    assert len(settings.events) == n and ('GENERATE', "villa", 2) not in scenario_rows()
    with pytest.raises(RuntimeError, match="No scenario preset 'castle_town'"):
        bpy.ops.worldpaint.load_village_preset(preset="castle_town")


def test_houses_have_walls_roofs_doors_and_windows_and_remember_their_type(grown):
    open_grown(grown)
    report = village_report()
    made = houses()
    kept = report["seeded"] - report["without_access"] - report["without_footprint"]
    print(f"{len(made)} houses for {report['requested']} requested: {report}")
    assert len(made) == kept, "a house for every seed with a parcel and a footprint"
    assert len(made) >= 0.5 * report["requested"], "most requested buildings stand"
    types, buildings = engine.encyclopedia_contents(engine.default_encyclopedia())
    counts = {}
    for obj in made:
        assert [m.name for m in obj.data.materials] == MATERIALS
        used = face_materials(obj.data)
        assert (used == 2).any() and (used == 3).any(), f"{obj.name} has a door and a window"
        assert (used == 0).any() and (used == 1).any()
        assert obj["wp_building"] in buildings and obj["wp_village_type"] == "farming"
        counts[obj["wp_building"]] = counts.get(obj["wp_building"], 0) + 1
    assert counts.get("church", 0) <= 1 and counts.get("house", 0) >= 5, "the hamlet's houses, at most one church"
    assert set(counts) <= {"church", "house", "farm", "villa"}
    assert len({m.data.name for m in made}) == len(made), "one mesh per house"


def test_houses_stand_beside_the_roads_never_on_them_nor_on_each_other(grown):
    open_grown(grown)
    width = village_report()["road_width"]
    roads = [spline_points(road_object(), s)[:, :2] for s in road_object().data.splines]
    road_samples = np.concatenate([densify(r, 0.5) for r in roads])
    closest, farthest = np.inf, 0.0
    footprints = [footprint(o) for o in houses()]
    for obj, corners in zip(houses(), footprints, strict=True):
        assert len(corners) == 4, f"{obj.name}'s walls stand on a quadrilateral"
        edge = densify(corners, 0.25, closed=True)
        d = distance_to_polylines(edge, roads).min()
        assert not polygon_contains(corners, road_samples).any(), f"a road runs through {obj.name}"
        closest, farthest = min(closest, d), max(farthest, d)
    print(f"{len(footprints)} houses: walls from {closest:.2f} m to {farthest:.2f} m off the road axes "
          f"(road width {width} m)")
    assert closest >= width / 2.0 - 0.1, "no wall in a road's corridor"
    assert farthest <= width / 2.0 + REACH, "every house within reach of a road"
    for i, a in enumerate(footprints):
        for b in footprints[i + 1:]:
            assert not polygon_contains(a, densify(b, 0.5, closed=True)).any(), "houses do not overlap"


def test_roads_and_their_ribbon_lie_on_the_terrain(grown):
    open_grown(grown)
    road = road_object()
    report = village_report()
    paths = [spline_points(road, s) for s in road.data.splines]
    nodes = np.concatenate(paths)
    off = np.abs(nodes[:, 2] - hill_height(nodes[:, 0], nodes[:, 1]))
    length = sum(np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1).sum() for p in paths)
    print(f"{len(paths)} roads, {length:.0f} m, {report['cycles']} cycles; nodes off the terrain ≤ {off.max():.3f} m")
    assert len(paths) >= 3 and off.max() < 0.05, "road nodes on the terrain"
    inside = (nodes[:, 0] - CENTER[0]) ** 2 + (nodes[:, 1] - CENTER[1]) ** 2 <= (RADIUS + 1.0) ** 2
    assert inside.all(), "the roads stay in the region"

    evaluated = road.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    area = sum(p.area for p in mesh.polygons)
    evaluated.to_mesh_clear()
    co = co.reshape(-1, 3)
    assert np.abs(co[:, 2] - hill_height(co[:, 0], co[:, 1])).max() < 0.1, "the ribbon is draped on the terrain"
    assert area == pytest.approx(report["road_width"] * length, rel=0.2), "a ribbon of the encyclopedia's width"
    parcels = next(o for o in village_collection().objects if o.get("wp_village") == "parcels")
    assert len(parcels.data.splines) == len(houses()) and all(s.use_cyclic_u for s in parcels.data.splines)


def test_save_and_reload_keep_the_village_and_the_scenario(grown):
    saved = open_grown(grown)
    settings = bpy.context.scene.worldpaint.village
    assert village_collection() is not None and village_collection().name == "Village"
    assert village_collection().name in bpy.data.collections["WorldPaint"].children
    reloaded = [(o.name, o["wp_building"], tuple(o.matrix_world.translation)) for o in houses()]
    assert reloaded == saved["houses"]
    assert scenario_rows() == saved["events"] and settings.report == saved["report"]
    assert settings.report.startswith(f"{len(reloaded)} houses, ")
    assert settings.region is not None and settings.region.name == "Region"


def test_undo_removes_a_village_in_one_step_and_a_second_village_replaces_the_first():
    hill_scene()
    assert bpy.ops.worldpaint.load_village_preset(preset="highland_hamlet") == {'FINISHED'}
    bpy.ops.ed.undo_push(message="scene built")
    assert bpy.ops.worldpaint.generate_village(seed=1) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="Generate Village")
    first = [(o.name, tuple(o.matrix_world.translation)) for o in houses()]
    n_objects = len(bpy.data.objects)
    assert first

    assert bpy.ops.worldpaint.generate_village(seed=2) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="Generate Village")
    second = [(o.name, tuple(o.matrix_world.translation)) for o in houses()]
    assert second != first
    assert len(bpy.data.collections["WorldPaint"].children) == 1, "one village collection"
    assert len(village_collection().objects) == len(second) + 1, "the second village's houses and roads only"
    made = [o for o in bpy.data.objects if o.get("wp_village")]
    assert len(made) == len(second) + 1, "the first village's objects are gone"

    bpy.ops.ed.undo()
    assert [(o.name, tuple(o.matrix_world.translation)) for o in houses()] == first, "one undo: the first village"
    assert len(bpy.data.objects) == n_objects
    bpy.ops.ed.undo()
    assert bpy.context.scene.worldpaint.village.collection is None, "one more: no village"
    assert not any(o.get("wp_village") for o in bpy.data.objects)
    assert "Village" not in bpy.data.collections


def data_counts():
    return {kind: len(getattr(bpy.data, kind)) for kind in ("collections", "objects", "meshes", "curves", "materials",
                                                             "node_groups")}


def tiny_terrain():
    """A 10 m plane as the terrain: too small for any building of the presets."""
    bpy.ops.mesh.primitive_plane_add(size=10.0, location=(1000.0, 1000.0, 0.0))
    plane = bpy.context.active_object
    bpy.context.scene.worldpaint.terrain = plane
    return plane


def test_a_village_that_builds_nothing_leaves_nothing_behind_and_says_why(capfd):
    tiny_terrain()
    assert bpy.ops.worldpaint.load_village_preset(preset="farming_hamlet") == {'FINISHED'}
    before, settings = data_counts(), bpy.context.scene.worldpaint.village
    capfd.readouterr()
    # a warning, not an error: the operator ends without a change
    assert bpy.ops.worldpaint.generate_village() == {'CANCELLED'}
    out = capfd.readouterr().out
    print(out)
    assert "Warning: Nothing could be built, the scene is unchanged: " in out
    # and why each building type found no place, from candidates the engine tried
    assert "no place for the church: 100% where nothing draws it" in out
    assert data_counts() == before, "no collection, object, mesh, curve, material or node group left behind"
    assert settings.collection is None and settings.report == ""


def test_a_village_that_builds_nothing_keeps_the_current_village(grown):
    open_grown(grown)
    settings = bpy.context.scene.worldpaint.village
    kept = [(o.name, tuple(o.matrix_world.translation)) for o in houses()]
    report = settings.report
    tiny_terrain()
    before = data_counts()
    assert bpy.ops.worldpaint.generate_village(whole_terrain=True) == {'CANCELLED'}
    assert data_counts() == before
    assert [(o.name, tuple(o.matrix_world.translation)) for o in houses()] == kept and settings.report == report


def test_the_reasons_nothing_was_built_come_from_the_engine_report():
    from worldpaint.bridge.village import nothing_built

    report = {"requested": 3, "seeded": 1, "fallbacks": 0, "unplaced": ["farm", "farm"], "unreachable": 0,
              "without_access": 1, "without_footprint": 0, "roads_over_max_grade": 0, "cycles": 0,
              "seconds": [0.0, 0.0, 0.0], "road_width": 5.0, "max_grade": 0.1}
    message = nothing_built(report)
    assert message.startswith("Nothing could be built, the scene is unchanged")
    assert "2 requested buildings unplaced (2 farm)" in message and "1 without road access" in message


def test_bad_inputs_are_reported_and_change_nothing(tmp_path):
    hill_scene()
    settings = bpy.context.scene.worldpaint.village
    assert bpy.ops.worldpaint.load_village_preset(preset="farming_hamlet") == {'FINISHED'}
    before = snapshot()
    bad = tmp_path / "encyclopedia.json"
    bad.write_text('{"version": 1, "roads": {"width": 5.0}, "buildings": {}}')
    with pytest.raises(RuntimeError, match="is not a usable building encyclopedia"):
        bpy.ops.worldpaint.generate_village(encyclopedia_path=str(bad))
    settings.encyclopedia_path = str(tmp_path / "missing.json")
    with pytest.raises(RuntimeError, match="Cannot read the encyclopedia file"):
        bpy.ops.worldpaint.generate_village()
    settings.encyclopedia_path = ""
    settings.events[2].building = "palace"
    with pytest.raises(RuntimeError, match="scenario event 3: unknown building type 'palace'"):
        bpy.ops.worldpaint.generate_village()
    settings.events[2].building = "house"
    settings.region.data.splines[0].use_cyclic_u = False
    with pytest.raises(RuntimeError, match="is not closed"):
        bpy.ops.worldpaint.generate_village()
    settings.region.data.splines[0].use_cyclic_u = True
    with pytest.raises(RuntimeError, match="No scenario preset"):
        bpy.ops.worldpaint.generate_village(preset="castle_town")
    bpy.context.scene.worldpaint.terrain = None
    with pytest.raises(RuntimeError, match="No terrain"):
        bpy.ops.worldpaint.generate_village()
    assert snapshot() == before, "nothing changed"


def interest_values(terrain_obj):
    values = np.empty(len(terrain_obj.data.vertices), dtype=np.float32)
    terrain_obj.data.attributes["wp_interest"].data.foreach_get("value", values)
    return values


def test_show_interest_colors_the_terrain_and_sees_the_village(grown):
    open_grown(grown)
    terrain_obj = bpy.context.scene.worldpaint.terrain
    mesh = terrain_obj.data
    assert bpy.ops.worldpaint.show_interest(village_type="farming", building="farm", criterion="slope") == {'FINISHED'}
    assert bpy.ops.worldpaint.show_interest(village_type="farming", building="house", criterion="INTEREST") \
        == {'FINISHED'}
    assert [a.name for a in mesh.color_attributes] == ["WorldPaint Interest"], "the second run replaced the first"
    assert mesh.color_attributes.active_color_name == "WorldPaint Interest"
    colors = np.empty(len(mesh.vertices) * 4, dtype=np.float32)
    mesh.color_attributes["WorldPaint Interest"].data.foreach_get("color", colors)
    colors = colors.reshape(-1, 4)
    values = interest_values(terrain_obj)
    print(f"interest of a house: {values.min():.2f}..{values.max():.2f}, {(values > 0).mean():.1%} positive")
    assert values.min() >= 0.0 and values.max() <= 1.0 and values.std() > 0.02
    assert colors[:, :3].std(axis=0).max() > 0.05, "the colors vary over the terrain"
    xy = world_vertices(terrain_obj)[:, :2]
    outside = (xy[:, 0] - CENTER[0]) ** 2 + (xy[:, 1] - CENTER[1]) ** 2 > (RADIUS + CELL) ** 2
    assert np.allclose(colors[outside, :3], 1.0), "white (0) outside the region"

    # sociability depends on the village's houses: it changes once they are gone
    assert bpy.ops.worldpaint.show_interest(building="house", criterion="sociability") == {'FINISHED'}
    with_village = interest_values(terrain_obj)
    for obj in houses():
        bpy.data.objects.remove(obj)
    assert bpy.ops.worldpaint.show_interest(building="house", criterion="sociability") == {'FINISHED'}
    without = interest_values(terrain_obj)
    assert with_village.min() < 0.0 or without.min() < 0.0, "criteria reach below 0 (blue)"
    assert np.abs(with_village - without).max() > 0.1, "the houses count in the sociability"
    with pytest.raises(RuntimeError, match="Unknown building type 'palace'"):
        bpy.ops.worldpaint.show_interest(building="palace")


def test_the_village_keeps_out_of_the_water_and_connects_where_it_is_told():
    hill_scene()
    scene = bpy.context.scene
    settings = scene.worldpaint.village
    water = bpy.data.collections.new("Water")
    scene.collection.children.link(water)
    a = np.linspace(0.0, 2.0 * np.pi, 32, endpoint=False)
    lake = np.column_stack([300.0 + 25.0 * np.cos(a), 150.0 + 18.0 * np.sin(a)])
    poly_curve("Lake", lake, True, water)
    river = np.column_stack([np.linspace(60.0, 340.0, 15), 300.0 + 10.0 * np.sin(np.linspace(0.0, 3.0, 15))])
    poly_curve("River", river, False, water)
    gate = bpy.data.objects.new("Gate", None)
    gate.location = (345.0, 200.0, 0.0)
    connections = bpy.data.collections.new("Connections")
    scene.collection.children.link(connections)
    connections.objects.link(gate)
    settings.water, settings.river_half_width = water, 5.0
    settings.use_water_level, settings.water_level = True, 3.0
    settings.connection_mode, settings.connections = 'EMPTIES', connections
    assert bpy.ops.worldpaint.load_village_preset(preset="fisherman_village") == {'FINISHED'}
    assert bpy.ops.worldpaint.generate_village(seed=5) == {'FINISHED'}

    made = houses()
    print(f"fisherman village: {settings.report}")
    assert len(made) >= 5
    for obj in made:
        corners = footprint(obj)
        assert not polygon_contains(lake, corners).any(), f"{obj.name} stands in the lake"
        assert distance_to_polylines(corners, [river]).min() >= 5.0, f"{obj.name} stands in the river"
        assert hill_height(corners[:, 0], corners[:, 1]).min() >= 3.0, f"{obj.name} stands below the water level"
    roads = [spline_points(road_object(), s)[:, :2] for s in road_object().data.splines]
    gap = distance_to_polylines(np.array([[345.0, 200.0]]), roads)[0]
    assert gap < 2.0 * CELL, f"the roads start at the connection point ({gap:.1f} m away)"

    # the water counts in the interest maps too: the water criterion changes once the lake and river are gone
    water_map = {"village_type": "fisherman", "building": "house", "criterion": "water"}
    assert bpy.ops.worldpaint.show_interest(**water_map) == {'FINISHED'}
    with_water = interest_values(scene.worldpaint.terrain)
    settings.water = None
    assert bpy.ops.worldpaint.show_interest(**water_map) == {'FINISHED'}
    without = interest_values(scene.worldpaint.terrain)
    xy = world_vertices(scene.worldpaint.terrain)[:, :2]
    by_the_lake = np.hypot(xy[:, 0] - 300.0, xy[:, 1] - 150.0) < 45.0
    print(f"water criterion by the lake: {with_water[by_the_lake].mean():.2f} with it, "
          f"{without[by_the_lake].mean():.2f} without")
    assert np.abs(with_water[by_the_lake] - without[by_the_lake]).mean() > 0.2


def test_a_custom_encyclopedia_and_a_scenario_file_drive_the_village(tmp_path):
    hill_scene()
    encyclopedia = json.loads(engine.default_encyclopedia())
    encyclopedia["village_types"]["hillfort"] = encyclopedia["village_types"]["defensive"]
    (tmp_path / "encyclopedia.json").write_text(json.dumps(encyclopedia))
    scenario = {"events": [{"event": "change_village_type", "village_type": "hillfort"},
                           {"event": "generate", "count": 8, "building": "house"}]}
    (tmp_path / "scenario.json").write_text(json.dumps(scenario))
    (tmp_path / "broken.json").write_text("{'events': ")
    files = {"scenario_path": str(tmp_path / "scenario.json")}
    with pytest.raises(RuntimeError, match="scenario event 1: unknown village type 'hillfort'"):
        bpy.ops.worldpaint.generate_village(**files)
    with pytest.raises(RuntimeError, match="is not JSON"):
        bpy.ops.worldpaint.generate_village(scenario_path=str(tmp_path / "broken.json"))
    assert not any(o.get("wp_village") for o in bpy.data.objects)

    files["encyclopedia_path"] = str(tmp_path / "encyclopedia.json")
    assert bpy.ops.worldpaint.generate_village(seed=2, **files) == {'FINISHED'}
    made = houses()
    assert made and all(o["wp_village_type"] == "hillfort" and o["wp_building"] == "house" for o in made)
    assert len(bpy.context.scene.worldpaint.village.events) == 0, "a scenario file leaves the list alone"


def test_village_operators_that_change_data_are_undoable():
    for op in ("generate_village", "show_interest", "load_village_preset", "add_village_event",
               "remove_village_event", "move_village_event"):
        assert 'UNDO' in getattr(bpy.types, f"WORLDPAINT_OT_{op}").bl_options, op
