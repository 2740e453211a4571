"""Roads cut into a slope through the Terrain panel's Embed Roads: the carriageway comes out level across, the
ground beyond the banks stays as it was, the change is one shape key that undo removes, and a village's houses move
with the ground under them."""

import bpy
import numpy as np
import pytest
from scene_kit import evaluated_vertices, grid_terrain, poly_curve, select_only

SIZE = 300.0
CELL = 2.0
ROAD_Y = 150.0
WIDTH = 5.0
BANKS = 8.0
KEY = "WorldPaint Embed Roads"


def slope_height(x, y):
    """A 15 % cross-slope with bumps along the road's direction (m)."""
    return 0.15 * y + 2.0 * np.sin(x / 15.0) + 0.5 * np.cos(y / 9.0)


def slope_scene():
    n = int(SIZE / CELL) + 1
    x, y = np.meshgrid(CELL * np.arange(n), CELL * np.arange(n))
    obj = grid_terrain("Terrain", (0.0, 0.0), CELL, slope_height(x, y))
    bpy.context.scene.worldpaint.terrain = obj
    return obj


def road_curve(name, xy):
    collection = bpy.data.collections.get("Roads") or bpy.data.collections.new("Roads")
    if collection.name not in bpy.context.scene.collection.children:
        bpy.context.scene.collection.children.link(collection)
    return poly_curve(name, xy, collection=collection)


def evaluated_heights(obj):
    """(ny, nx) heights of the terrain grid as it is shown (shape keys applied)."""
    n = int(SIZE / CELL) + 1
    return evaluated_vertices(obj)[:, 2].reshape(n, n)


def node(v):
    return int(round(v / CELL))


def test_a_road_across_a_slope_gets_a_level_carriageway_and_the_land_beyond_its_banks_stays():
    terrain = slope_scene()
    road_curve("Road", np.array([[20.0, ROAD_Y], [280.0, ROAD_Y]]))
    before = evaluated_heights(terrain)
    assert bpy.ops.worldpaint.embed_roads(roads="Roads", width=WIDTH, bank_width=BANKS) == {'FINISHED'}
    keys = terrain.data.shape_keys.key_blocks
    assert KEY in keys and keys[KEY].value == 1.0
    after = evaluated_heights(terrain)

    # across the carriageway (nodes 2 m either side of the centreline), from x = 40 m to 260 m
    j = node(ROAD_Y)
    i = np.arange(node(40.0), node(260.0) + 1)
    cross = np.abs(after[j + 1, i] - after[j - 1, i]) / (2.0 * CELL)
    natural = np.abs(before[j + 1, i] - before[j - 1, i]) / (2.0 * CELL)
    print(f"cross-slope on the carriageway: max {cross.max():.4f} (natural {natural.mean():.3f})")
    assert cross.max() < 0.02
    # along it the grade changes smoothly: no step between consecutive 2 m samples of the grade
    kinks = np.abs(np.diff(after[j, i], 2))
    print(f"largest change of height difference between consecutive 2 m samples: {kinks.max() * 100:.1f} cm")
    assert kinks.max() < 0.05
    # beyond half the width and the banks, the terrain is untouched (the rows a full cell further out)
    far = node(WIDTH / 2 + BANKS) + 1
    untouched = np.abs(after - before)
    untouched[j - far + 1:j + far, :] = 0.0
    print(f"largest change beyond the banks: {untouched.max() * 1000:.3f} mm")
    assert untouched.max() < 1e-3
    # the uphill edge of the carriageway is cut and the downhill edge filled (the slope falls 0.3 m over 2 m)
    change = (after - before)[:, i].mean(axis=1)
    assert change[j + 1] < -0.2 and change[j - 1] > 0.2, (change[j + 1], change[j - 1])


def spur_height(x, y):
    """A 12 % slope with spurs running down it, 2 m high and 40 m apart, a crest on x = 150 m (m)."""
    return 0.12 * y + 2.0 * np.cos(2.0 * np.pi * (x - 150.0) / 40.0)


def test_crossing_roads_meet_without_a_step_and_stay_level_across():
    n = int(SIZE / CELL) + 1
    x, y = np.meshgrid(CELL * np.arange(n), CELL * np.arange(n))
    terrain = grid_terrain("Terrain", (0.0, 0.0), CELL, spur_height(x, y))
    bpy.context.scene.worldpaint.terrain = terrain
    # along the contour, and down the spur's crest: their smoothed profiles differ where they cross
    road_curve("Road along", np.array([[20.0, 150.0], [280.0, 150.0]]))
    road_curve("Road down", np.array([[150.0, 20.0], [150.0, 280.0]]))
    assert bpy.ops.worldpaint.embed_roads(roads="Roads", width=WIDTH, bank_width=BANKS) == {'FINISHED'}
    after = evaluated_heights(terrain)

    # along each centreline (a row and a column of the grid), 40 m either side of the crossing: the terrain is
    # linear between vertices there, so a step between samples 10 cm apart is a twentieth of a vertex step
    c = node(150.0)
    near = np.arange(c - node(40.0), c + node(40.0) + 1)
    along, down = after[c, near], after[near, c]
    steps = {name: np.abs(np.diff(z)).max() / 20.0 for name, z in (("along", along), ("down", down))}
    print("largest step between samples 10 cm apart through the crossing: "
          + ", ".join(f"{name} {step * 100:.2f} cm" for name, step in steps.items()))
    assert max(steps.values()) < 0.05
    # each is level across outside the crossing square
    outside = np.abs(near - c) > node(WIDTH / 2) + 1
    cross_along = np.abs(after[c + 1, near] - after[c - 1, near])[outside] / (2.0 * CELL)
    cross_down = np.abs(after[near, c + 1] - after[near, c - 1])[outside] / (2.0 * CELL)
    print(f"cross-slope outside the crossing square: along {cross_along.max() * 100:.2f} %, "
          f"down {cross_down.max() * 100:.2f} %")
    assert max(cross_along.max(), cross_down.max()) < 0.02


def test_a_second_run_replaces_the_first_and_undo_removes_it():
    terrain = slope_scene()
    road_curve("Road", np.array([[20.0, ROAD_Y], [280.0, ROAD_Y]]))
    bpy.ops.ed.undo_push(message="scene built")
    assert bpy.ops.worldpaint.embed_roads(roads="Roads", width=WIDTH, bank_width=BANKS) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="Embed Roads")
    first = evaluated_heights(terrain)
    assert bpy.ops.worldpaint.embed_roads(roads="Roads", width=WIDTH, bank_width=BANKS) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="Embed Roads")
    terrain = bpy.data.objects["Terrain"]
    assert [k.name for k in terrain.data.shape_keys.key_blocks] == ["Basis", KEY], "one key, replaced"
    assert np.abs(evaluated_heights(terrain) - first).max() < 1e-4, "the same cut, not twice as deep"
    bpy.ops.ed.undo()
    bpy.ops.ed.undo()
    terrain = bpy.data.objects["Terrain"]
    assert terrain.data.shape_keys is None or KEY not in terrain.data.shape_keys.key_blocks


def test_no_road_is_reported_and_the_terrain_is_left_as_it_was():
    terrain = slope_scene()
    with pytest.raises(RuntimeError, match="No road to embed"):
        bpy.ops.worldpaint.embed_roads()
    assert terrain.data.shape_keys is None
    with pytest.raises(RuntimeError, match="No collection named"):
        bpy.ops.worldpaint.embed_roads(roads="Nowhere")
    assert terrain.data.shape_keys is None


def test_a_curve_of_a_single_point_is_named_and_why_it_is_no_road(capfd):
    terrain = slope_scene()
    dot = road_curve("Dot", np.array([[150.0, ROAD_Y]]))
    single = "curve 'Dot' has a single point; a road needs at least two"
    with pytest.raises(RuntimeError, match=f"No road to embed in the collection 'Roads': {single}"):
        bpy.ops.worldpaint.embed_roads(roads="Roads")
    select_only([dot])
    with pytest.raises(RuntimeError, match=f"No road to embed: {single}"):
        bpy.ops.worldpaint.embed_roads()
    assert terrain.data.shape_keys is None
    # beside a real road it is left out, and said so
    road_curve("Road", np.array([[20.0, ROAD_Y], [280.0, ROAD_Y]]))
    capfd.readouterr()
    assert bpy.ops.worldpaint.embed_roads(roads="Roads", width=WIDTH, bank_width=BANKS) == {'FINISHED'}
    out = capfd.readouterr().out
    assert "Embedded 1 road(s)" in out and f"Warning: Left out: {single}" in out


def test_village_roads_are_embedded_and_the_houses_move_with_the_ground():
    terrain = slope_scene()
    village = bpy.context.scene.worldpaint.village
    assert bpy.ops.worldpaint.load_village_preset(preset="farming_hamlet") == {'FINISHED'}
    assert bpy.ops.worldpaint.generate_village(seed=2, whole_terrain=True) == {'FINISHED'}
    houses = [o for o in village.collection.objects if o.get("wp_village") == "house"]
    assert houses
    import worldpaint_engine as engine
    from worldpaint.bridge.terrain import mesh_arrays

    def ground(xy):
        vertices, triangles = mesh_arrays(terrain, bpy.context.evaluated_depsgraph_get())
        return engine.Terrain(vertices, triangles).heights_at(np.ascontiguousarray(xy))

    xy = np.array([o.location[:2] for o in houses])
    above = np.array([o.location.z for o in houses]) - ground(xy)
    assert bpy.ops.worldpaint.embed_roads(width=5.0, bank_width=6.0) == {'FINISHED'}
    moved = np.array([o.location.z for o in houses]) - ground(xy)
    print(f"{len(houses)} houses; ground change under them up to "
          f"{np.abs(np.array([o['wp_seat_roads'] for o in houses])).max():.2f} m")
    assert np.abs(moved - above).max() < 0.05, "each house keeps its height above the ground"
    # a second run does not move them twice
    assert bpy.ops.worldpaint.embed_roads(width=5.0, bank_width=6.0) == {'FINISHED'}
    again = np.array([o.location.z for o in houses]) - ground(xy)
    assert np.abs(again - above).max() < 0.05
