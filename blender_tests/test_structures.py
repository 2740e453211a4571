"""Roads learned from a hand-drawn village and pasted elsewhere through the operators: the new roads are curve
objects whose ribbon lies on the terrain, and the new houses keep off the roads, along them."""

import bpy
import numpy as np
import pytest
import worldpaint_engine as engine
from scene_kit import grid_terrain, select_only, village_exemplar, village_height
from worldpaint.bridge.curves import PROFILE_LIFT, structure_objects
from worldpaint.bridge.engine import exemplar_hard_core
from worldpaint.bridge.geometry import spline_control_points as spline_points
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

EXEMPLAR = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (300.0, 300.0)}
DESTINATION = {"region_mode": 'RECT', "rect_min": (450.0, 0.0), "rect_max": (750.0, 300.0)}
WIDTH = 6.0


def segments_of(paths):
    """(start (M, 2), end (M, 2)) of every segment of the given polylines (N_k, 2)."""
    starts = np.concatenate([p[:-1] for p in paths])
    ends = np.concatenate([p[1:] for p in paths])
    return starts, ends


def distance_to_segments(xy, starts, ends):
    """Distance from each point (N, 2) to the nearest segment."""
    d = ends - starts
    length2 = np.maximum((d * d).sum(axis=1), 1e-12)
    t = np.clip(((xy[:, None, :] - starts[None]) * d[None]).sum(axis=2) / length2, 0.0, 1.0)
    nearest = starts[None] + t[..., None] * d[None]
    return np.sqrt(((xy[:, None, :] - nearest) ** 2).sum(axis=2)).min(axis=1)


def evaluated_mesh(obj):
    """World vertices (N, 3) and face area of an object's evaluated mesh (a curve's ribbon)."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        co = np.empty(len(mesh.vertices) * 3)
        mesh.vertices.foreach_get("co", co)
        return co.reshape(-1, 3), sum(p.area for p in mesh.polygons)
    finally:
        evaluated.to_mesh_clear()


def learn_and_paste():
    terrain_obj, roads, houses, _ = village_exemplar()
    select_only([roads, *houses])
    assert bpy.ops.worldpaint.learn_color(name="Village", **EXEMPLAR) == {'FINISHED'}
    settings = bpy.context.scene.worldpaint
    kinds = {c.name: (c.kind, c.layer) for c in settings.categories}
    assert kinds == {"road": ("graph", "settlement"), "House": ("distribution", "default")}
    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=3, **DESTINATION) == {'FINISHED'}
    return terrain_obj, roads


def test_pasted_roads_are_curves_on_the_terrain_and_houses_keep_off_them():
    terrain_obj, roads = learn_and_paste()
    scene = bpy.context.scene
    road_obj = structure_objects(scene).get("road")
    assert road_obj is not None, "the pasted roads are a curve object"
    assert road_obj.users_collection[0].name == "WP settlement", "laid into the WorldPaint collection by layer"
    paths = [spline_points(road_obj, s) for s in road_obj.data.splines]
    nodes = np.concatenate(paths)
    length = sum(np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1).sum() for p in paths)
    print(f"{len(paths)} new roads, {len(nodes)} vertices, {length:.0f} m")
    assert len(paths) >= 10 and length > 1500.0
    assert np.abs(nodes[:, 2] - village_height(nodes[:, 0], nodes[:, 1])).max() < 0.05, "nodes on the terrain"

    # the ribbon: flat, the category's width, every vertex on the terrain surface
    co, area = evaluated_mesh(road_obj)
    off = np.abs(co[:, 2] - village_height(co[:, 0], co[:, 1]))
    print(f"ribbon: {len(co)} vertices, height off the terrain ≤ {off.max():.3f} m, area {area:.0f} m² "
          f"for {WIDTH * length:.0f} m² of width × length")
    assert off.max() < 0.05, "every ribbon vertex within 5 cm of the terrain"
    assert abs(area / (WIDTH * length) - 1.0) < 0.15, "a flat ribbon of the road's width"

    # houses along the roads, never on them
    house_co = point_cloud_arrays(point_cloud_objects(scene)["House"])[0]
    inside = (house_co[:, 0] >= 450.0) & (house_co[:, 0] <= 750.0)
    assert inside.sum() > 50
    drawn = [spline_points(roads, s)[:, :2] for s in roads.data.splines]
    distance = distance_to_segments(house_co[inside, :2], *segments_of([p[:, :2] for p in paths] + drawn))
    print(f"{inside.sum()} houses: closest to a road {distance.min():.1f} m, median {np.median(distance):.1f} m, "
          f"{(distance >= 8.0).mean():.1%} at 8 m or more")
    assert distance.min() > WIDTH / 2.0, "no house on a road"
    assert 8.0 <= np.median(distance) <= 15.0, "houses stay in the band they were learned in"


def test_roads_pasted_on_a_second_terrain_leave_the_first_terrains_ribbons_on_it():
    # one curve object per category drapes on one terrain, the last pasted on: the ribbons of the roads on the other
    # keep their curves' heights (within the road's cross slope), lifted as draped ones are
    terrain_obj, _ = learn_and_paste()
    x = 5000.0 + 2.0 * np.arange(201)
    far = grid_terrain("Far hills", (5000.0, 0.0), 2.0, 40.0 + 0.05 * (x[None, :] - 5000.0) + np.zeros((151, 1)))
    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=4, terrain=far.name, region_mode='RECT', rect_min=(5050.0, 0.0),
                                          rect_max=(5350.0, 300.0)) == {'FINISHED'}
    co, _ = evaluated_mesh(structure_objects(bpy.context.scene)["road"])
    inner = (co[:, 1] > 5.0) & (co[:, 1] < 295.0)  # off the far terrain's edges, where no ray hits it
    here, there = co[inner & (co[:, 0] < 1000.0)], co[inner & (co[:, 0] > 4000.0)]
    above_here = here[:, 2] - village_height(here[:, 0], here[:, 1])
    off_there = np.abs(there[:, 2] - (40.0 + 0.05 * (there[:, 0] - 5000.0)))
    print(f"ribbons: {len(here)} vertices on the first terrain within {np.abs(above_here).max():.3f} m of it (median "
          f"{np.median(above_here):.3f} m above), {len(there)} on the second within {off_there.max():.3f} m")
    assert len(here) > 1000 and len(there) > 1000
    assert off_there.max() < 0.1, "the last pasted roads drape on their terrain"
    assert np.abs(above_here).max() < 0.5, "the first terrain's roads stay on it"
    assert np.median(above_here) >= 0.5 * PROFILE_LIFT, "lifted as the draped ones are, so they do not flicker into it"


def test_undo_and_a_second_paste_replace_the_synthesized_roads_only():
    _, roads = learn_and_paste()
    scene = bpy.context.scene
    road_obj = structure_objects(scene)["road"]
    first = np.concatenate([spline_points(road_obj, s) for s in road_obj.data.splines])
    n_first = len(road_obj.data.splines)
    drawn = len(roads.data.splines)
    # background mode pushes no undo step after an operator; push them as the UI does (see test_scene_life)
    bpy.ops.ed.undo_push(message="first paste")
    assert bpy.ops.worldpaint.paste_color(seed=4, **DESTINATION) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="Paste Color")
    road_obj = structure_objects(scene)["road"]
    second = [spline_points(road_obj, s) for s in road_obj.data.splines]
    assert len(roads.data.splines) == drawn, "hand-drawn roads are never touched"
    assert abs(len(second) - n_first) <= 0.5 * n_first, "the second paste replaced the first, not added to it"
    nodes = np.concatenate(second)
    assert (nodes[:, 0] >= 450.0 - 1e-6).all() and (nodes[:, 0] <= 750.0 + 1e-6).all()

    bpy.ops.ed.undo()
    road_obj = structure_objects(bpy.context.scene)["road"]
    restored = np.concatenate([spline_points(road_obj, s) for s in road_obj.data.splines])
    assert restored.shape == first.shape and np.allclose(restored, first), "one undo brings the first roads back"


def test_switching_off_the_road_interaction_lets_houses_stand_on_roads():
    learn_and_paste()
    scene = bpy.context.scene
    color = scene.worldpaint.palette["Village"]
    rows = {(i.category, i.other): (k, i.how) for k, i in enumerate(color.interactions)}
    index, how = rows[("House", "road")]
    assert "distance to graph" in how, "houses learned their distance to the roads"
    assert bpy.ops.worldpaint.toggle_interaction(index=index) == {'FINISHED'}
    assert not color.interactions[index].enabled
    summary = engine.color_summary(color.json)
    assert all(tuple(m)[:2] != ("House", "road") for m in summary["maps"] + summary["pairs"])
    assert bpy.ops.worldpaint.paste_color(seed=3, **DESTINATION) == {'FINISHED'}

    road_obj = structure_objects(scene)["road"]
    paths = [spline_points(road_obj, s)[:, :2] for s in road_obj.data.splines]
    house_co = point_cloud_arrays(point_cloud_objects(scene)["House"])[0]
    inside = (house_co[:, 0] >= 450.0) & (house_co[:, 0] <= 750.0)
    distance = distance_to_segments(house_co[inside, :2], *segments_of(paths))
    on_road = int((distance < WIDTH / 2.0).sum())
    print(f"road interaction off: {inside.sum()} houses, {on_road} on a road")
    assert on_road >= 3, "without the interaction the roads no longer keep the houses off"

    assert bpy.ops.worldpaint.toggle_interaction(index=index) == {'FINISHED'}
    assert color.json == color.learned_json, "switched on again, the color is the learned one"


def inside_any(contours, xy):
    """Which points (N, 2) lie inside one of the contours (non-overlapping islands)."""
    xy = np.ascontiguousarray(xy, dtype=np.float64)
    inside = np.zeros(len(xy), dtype=bool)
    for c in contours:
        inside |= engine.region_contains({"shape": "polygon", "points": np.asarray(c)[:, :2].tolist()}, xy)
    return inside


def island_exemplar():
    """Four wobbly islands drawn as closed curves (curve data "island") in a 200 m square of sea, trees on them."""
    from scene_kit import collection_instances, grid_terrain, prototypes

    x, y = np.meshgrid(np.arange(-100.0, 601.0, 2.0), np.arange(-100.0, 301.0, 2.0))
    terrain_obj = grid_terrain("Terrain", (-100.0, -100.0), 2.0, village_height(x, y))
    bpy.context.scene.worldpaint.terrain = terrain_obj
    prototypes()
    curve = bpy.data.curves.new("island", 'CURVE')
    curve.dimensions = '3D'
    contours = []
    for cx, cy, r in ((50.0, 50.0, 30.0), (150.0, 60.0, 25.0), (60.0, 150.0, 28.0), (150.0, 150.0, 32.0)):
        a = np.linspace(0.0, 2.0 * np.pi, 48, endpoint=False)
        rr = r * (1.0 + 0.15 * np.sin(3.0 * a + cx))
        xy = np.column_stack([cx + rr * np.cos(a), cy + rr * np.sin(a)])
        contours.append(xy)
        spline = curve.splines.new('POLY')
        spline.points.add(len(xy) - 1)
        spline.points.foreach_set("co", np.column_stack([xy, village_height(xy[:, 0], xy[:, 1]),
                                                         np.ones(len(xy))]).ravel())
        spline.use_cyclic_u = True
    islands = bpy.data.objects.new("Islands", curve)
    bpy.context.scene.collection.objects.link(islands)
    region = {"shape": "rect", "min": [0.0, 0.0], "max": [200.0, 200.0]}
    xy = exemplar_hard_core(region, 0.01, 4.0, 2)
    on_land = inside_any(contours, xy)
    trees = collection_instances("Tree", xy[on_land], village_height(xy[on_land, 0], xy[on_land, 1]))
    return islands, trees


def test_pasted_islands_are_closed_curves_with_a_filled_mesh_on_the_terrain_and_trees_on_land():
    islands, trees = island_exemplar()
    select_only([islands, *trees])
    assert bpy.ops.worldpaint.learn_color(name="Islands", region_mode='RECT', rect_min=(0.0, 0.0),
                                          rect_max=(200.0, 200.0)) == {'FINISHED'}
    kinds = {c.name: (c.kind, c.layer) for c in bpy.context.scene.worldpaint.categories}
    assert kinds["island"] == ("polygon", "terrain")
    select_only([])
    assert bpy.ops.worldpaint.paste_color(seed=2, region_mode='RECT', rect_min=(250.0, 0.0),
                                          rect_max=(550.0, 200.0)) == {'FINISHED'}
    scene = bpy.context.scene
    island_obj = structure_objects(scene)["island"]
    assert island_obj.users_collection[0].name == "WP terrain"
    contours = [spline_points(island_obj, s) for s in island_obj.data.splines]
    assert len(contours) >= 3 and all(s.use_cyclic_u for s in island_obj.data.splines)

    fill = next(o for o in scene.objects if o.get("wp_fill") == "island")
    co = np.empty(len(fill.data.vertices) * 3)
    fill.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    area = sum(p.area for p in fill.data.polygons)
    # a contour inside another is a lake in an island (even-odd): its area is water
    depth = [sum(bool(engine.region_contains({"shape": "polygon", "points": o[:, :2]}, c[:1, :2])[0])
                 for o in contours if o is not c) for c in contours]
    land_area = sum((-1) ** d * engine.region_area({"shape": "polygon", "points": c[:, :2].tolist()})
                    for c, d in zip(contours, depth, strict=True))
    print(f"{len(contours)} contours ({sum(d % 2 for d in depth)} lakes), {land_area:.0f} m² of land; "
          f"fill: {len(co)} vertices, {area:.0f} m² "
          f"(projected), height off the terrain ≤ {np.abs(co[:, 2] - village_height(co[:, 0], co[:, 1])).max():.3f} m")
    assert np.abs(co[:, 2] - village_height(co[:, 0], co[:, 1])).max() < 0.05, "the fill lies on the terrain"
    assert area == pytest.approx(land_area, rel=0.02), "the fill covers the islands (its slope adds a little)"
    drawn = [spline_points(islands, s) for s in islands.data.splines]
    share = land_area / (300.0 * 200.0)
    learned = sum(engine.region_area({"shape": "polygon", "points": c[:, :2].tolist()}) for c in drawn) / 200.0**2
    print(f"land: {learned:.3f} of the example, {share:.3f} of the destination")
    assert share == pytest.approx(learned, rel=0.25), "the islands keep their share of the land"
    # an archipelago keeps the example's contours per area and mean island area (the example has no lakes)
    per_ha, learned_per_ha = len(contours) / 6.0, len(drawn) / 4.0
    mean, learned_mean = land_area / sum(d % 2 == 0 for d in depth), learned * 200.0**2 / len(drawn)
    print(f"{per_ha:.2f} contours per ha (example {learned_per_ha:.2f}), mean island {mean:.0f} m² "
          f"(example {learned_mean:.0f} m²)")
    assert per_ha == pytest.approx(learned_per_ha, rel=0.25), "as many contours per area as the example"
    assert mean == pytest.approx(learned_mean, rel=0.25), "islands as large as the example's"

    tree_co = point_cloud_arrays(point_cloud_objects(scene)["Tree"])[0]
    pasted = tree_co[tree_co[:, 0] >= 250.0]
    wet = int((~inside_any(contours, pasted[:, :2])).sum())
    print(f"{len(pasted)} trees, {wet} in water")
    assert len(pasted) > 20 and wet == 0, "trees learned on islands never land in water"


def test_clear_region_cuts_the_synthesized_roads_at_its_border():
    learn_and_paste()
    scene = bpy.context.scene
    before = [spline_points(structure_objects(scene)["road"], s) for s in structure_objects(scene)["road"].data.splines]
    assert bpy.ops.worldpaint.clear_region(region_mode='RECT', rect_min=(450.0, 0.0),
                                           rect_max=(600.0, 300.0)) == {'FINISHED'}
    road_obj = structure_objects(scene)["road"]
    after = [spline_points(road_obj, s) for s in road_obj.data.splines]
    assert all((p[:, 0] >= 600.0 - 1e-4).all() for p in after), "no synthesized road left in the cleared region"
    kept = sum(np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1).sum() for p in after)
    total = sum(np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1).sum() for p in before)
    assert 0.2 * total < kept < 0.8 * total
    house_co = point_cloud_arrays(point_cloud_objects(scene)["House"])[0]
    assert not ((house_co[:, 0] > 450.0) & (house_co[:, 0] < 600.0)).any()


def test_the_eraser_cuts_roads_under_the_brush_and_leaves_no_stub_shorter_than_the_colors_shortest_edge():
    learn_and_paste()
    scene = bpy.context.scene
    shortest = dict(engine.color_summary(scene.worldpaint.palette["Village"].json)["shortest_edges"])["road"]
    houses = point_cloud_arrays(point_cloud_objects(scene)["House"])[0].copy()
    road_obj = structure_objects(scene)["road"]
    before = sum(np.linalg.norm(np.diff(spline_points(road_obj, s)[:, :2], axis=0), axis=1).sum()
                 for s in road_obj.data.splines)
    line = [(float(x), 150.0) for x in np.linspace(460.0, 740.0, 15)]
    stroke = [{"name": "", "location": (x, y, 0.0)} for x, y in line]
    assert bpy.ops.worldpaint.erase(stroke=stroke, radius=12.0, category="road") == {'FINISHED'}
    road_obj = structure_objects(scene)["road"]
    paths = [spline_points(road_obj, s)[:, :2] for s in road_obj.data.splines]
    lengths = [np.linalg.norm(np.diff(p, axis=0), axis=1).sum() for p in paths]
    print(f"\nroads {before:.0f} m -> {sum(lengths):.0f} m in {len(paths)} pieces, the shortest {min(lengths):.1f} m; "
          f"the color's shortest edge {shortest:.1f} m")
    assert 0.3 * before < sum(lengths) < 0.97 * before
    assert min(lengths) >= shortest
    starts, ends = segments_of(paths)
    on_stroke = np.array(line)
    assert distance_to_segments(on_stroke, starts, ends).min() >= 12.0 - 1e-3, "no road left under the brush"
    assert np.array_equal(point_cloud_arrays(point_cloud_objects(scene)["House"])[0], houses), "houses stay"


def road_network(scene):
    """The synthesized roads' polylines (N_k, 2) and their dangling ends: endpoints no other road passes within
    1 m of (dead ends)."""
    road_obj = structure_objects(scene)["road"]
    paths = [spline_points(road_obj, s)[:, :2] for s in road_obj.data.splines]
    dangling = []
    for k, path in enumerate(paths):
        others = [p for j, p in enumerate(paths) if j != k]
        if not others:
            continue
        starts, ends = segments_of(others)
        ends_of_path = np.array([path[0], path[-1]])
        dangling += list(ends_of_path[distance_to_segments(ends_of_path, starts, ends) > 1.0])
    return paths, np.array(dangling).reshape(-1, 2)


def road_per_house(scene, x0, x1):
    paths, _ = road_network(scene)
    length = 0.0
    for p in paths:
        mid = 0.5 * (p[1:] + p[:-1])
        inside = (mid[:, 0] > x0) & (mid[:, 0] < x1) & (mid[:, 1] > 0.0) & (mid[:, 1] < 300.0)
        length += np.linalg.norm(np.diff(p, axis=0), axis=1)[inside].sum()
    houses = point_cloud_arrays(point_cloud_objects(scene)["House"])[0]
    inside = (houses[:, 0] > x0) & (houses[:, 0] < x1) & (houses[:, 1] > 0.0) & (houses[:, 1] < 300.0)
    return length / max(int(inside.sum()), 1)


def test_stretching_a_village_stretches_its_roads_without_tearing_them():
    learn_and_paste()
    scene = bpy.context.scene
    _, dangling_before = road_network(scene)
    per_house_before = road_per_house(scene, 450.0, 750.0)
    assert bpy.ops.worldpaint.stretch_region(region_mode='RECT', rect_min=(450.0, 0.0), rect_max=(750.0, 300.0),
                                             side='EAST', amount=60.0, color="Village", seed=4) == {'FINISHED'}
    paths, dangling_after = road_network(scene)
    per_house_after = road_per_house(scene, 450.0, 810.0)
    assert max(p[:, 0].max() for p in paths) > 780.0, "the roads beyond the cut moved with the dragged side"
    print(f"\ndangling road ends {len(dangling_before)} -> {len(dangling_after)}; road per house "
          f"{per_house_before:.1f} m -> {per_house_after:.1f} m")
    # each dead end after the stretch was one before (where it stood, or moved with its side)
    moved = np.vstack([dangling_before, dangling_before + [60.0, 0.0]]) if len(dangling_before) else np.zeros((0, 2))
    for end in dangling_after:
        assert len(moved) and np.linalg.norm(moved - end, axis=1).min() < 1.0, f"a new dead end at {end}"
    assert abs(per_house_after - per_house_before) <= 0.15 * per_house_before


def test_a_brush_stroke_paints_roads_on_the_terrain_within_its_reach():
    learn_and_paste()
    scene = bpy.context.scene
    before = len(structure_objects(scene)["road"].data.splines)
    stroke = [{"name": "", "location": (float(x), 150.0, 0.0)} for x in range(320, 440, 10)]
    assert bpy.ops.worldpaint.brush(stroke=stroke, radius=40.0, color="Village", seed=5) == {'FINISHED'}
    road_obj = structure_objects(scene)["road"]
    paths = [spline_points(road_obj, s) for s in road_obj.data.splines]
    painted = [p for p in paths if (p[:, 0] < 450.0).any()]
    print(f"{len(road_obj.data.splines) - before} roads painted by the stroke")
    assert painted, "the stroke painted roads"
    assert all(np.abs(p[:, 2] - village_height(p[:, 0], p[:, 1])).max() < 0.05 for p in painted)
    starts, ends = segments_of([p[:, :2] for p in painted])
    assert (np.abs(starts[:, 1] - 150.0) <= 40.0 + 1e-6).all() and (np.abs(ends[:, 1] - 150.0) <= 40.0 + 1e-6).all()


def test_an_oriented_pair_is_learned_on_request_and_a_bad_one_is_reported():
    _, roads, houses, _ = village_exemplar()
    select_only([roads, *houses])
    with pytest.raises(RuntimeError, match="not of the form"):
        bpy.ops.worldpaint.learn_color(name="Bad", oriented="House-road", **EXEMPLAR)
    with pytest.raises(RuntimeError, match="no category castle"):
        bpy.ops.worldpaint.learn_color(name="Bad", oriented="House:castle", **EXEMPLAR)
    with pytest.raises(RuntimeError, match="seen through its distance"):
        bpy.ops.worldpaint.learn_color(name="Bad", oriented="House:road", **EXEMPLAR)
    assert len(bpy.context.scene.worldpaint.palette) == 0, "nothing learned from a bad request"
    assert bpy.ops.worldpaint.learn_color(name="Rows", oriented="House:House", **EXEMPLAR) == {'FINISHED'}
    color = bpy.context.scene.worldpaint.palette["Rows"]
    how = {(i.category, i.other): i.how for i in color.interactions}
    assert how[("House", "House")] == "rdf, oriented rdf"
    assert how[("House", "road")] == "distance to graph", "houses see the roads through their distance"


def test_moving_a_region_carries_its_roads_onto_the_terrain_where_they_land():
    learn_and_paste()
    scene = bpy.context.scene
    before = [spline_points(structure_objects(scene)["road"], s) for s in structure_objects(scene)["road"].data.splines]
    assert bpy.ops.worldpaint.move_region(region_mode='RECT', rect_min=(450.0, 0.0), rect_max=(600.0, 300.0),
                                          offset=(290.0, 0.0)) == {'FINISHED'}
    road_obj = structure_objects(scene)["road"]
    after = np.concatenate([spline_points(road_obj, s) for s in road_obj.data.splines])
    inside = (after[:, 0] > 450.0 + 1e-4) & (after[:, 0] < 600.0 - 1e-4)
    assert not inside.any(), "the source is left without its roads"
    landed = after[(after[:, 0] > 740.0 + 1e-4) & (after[:, 0] < 890.0 - 1e-4)]
    moved = np.concatenate(before)
    moved = moved[(moved[:, 0] > 450.0 + 1e-4) & (moved[:, 0] < 600.0 - 1e-4)]
    assert len(landed) >= len(moved) > 0
    assert np.abs(landed[:, 2] - village_height(landed[:, 0], landed[:, 1])).max() < 0.05, "on the terrain there"


def test_a_river_is_a_ribbon_with_a_bed_below_the_terrain():
    terrain_obj, roads, houses, _ = village_exemplar()
    roads.data.name = "river"
    select_only([roads])
    assert bpy.ops.worldpaint.learn_color(name="Rivers", **EXEMPLAR) == {'FINISHED'}
    settings = bpy.context.scene.worldpaint
    settings.categories["river"].width, settings.categories["river"].depth = 12.0, 1.5
    assert bpy.ops.worldpaint.paste_color(seed=3, **DESTINATION) == {'FINISHED'}
    river = structure_objects(bpy.context.scene)["river"]
    co, _ = evaluated_mesh(river)
    below = village_height(co[:, 0], co[:, 1]) - co[:, 2]
    print(f"river bed: {len(co)} vertices, from {-below.max():.2f} m to {-below.min():.2f} m about the terrain")
    assert below.max() == pytest.approx(1.5 - 0.02, abs=0.1), "the middle lies the depth below the terrain"
    assert below.min() == pytest.approx(-0.02, abs=0.03), "the banks lie on the terrain"
