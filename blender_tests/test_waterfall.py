"""A waterfall scene drawn as curves on a cliff (contact → free-fall → pool → contact) through the Terrain panel's
Build Waterfall: the terrain changes in one shape key, the water mesh carries its decoration attributes and lies over
the riverbed, instances keep out of the water, river rocks are synthesized in the water (from the built-in river rocks
or a palette color the user learned), undo removes all of it, and the controllers' roles survive a save."""

import bpy
import numpy as np
import pytest
from scene_kit import evaluated_vertices, grid_terrain, hard_core_examples, poly_curve, prototypes, select_only

CELL = 2.0
NX, NY = 151, 101  # 300 m by 200 m
KEY = "WorldPaint Waterfall"
POOL = (140.0, 100.0, 10.0, 9.0)  # centre x, y, radius, level


def cliff_height(x, y):
    """A plateau falling gently east, a 16 m cliff at x = 120..126, and a valley below it (m)."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    plateau = 30.0 - 0.03 * x
    valley = 10.0 - 0.03 * (x - 126.0)
    t = np.clip((x - 120.0) / 6.0, 0.0, 1.0)
    return (1.0 - t) * plateau + t * valley + 0.3 * np.sin(y / 7.0)


def curve(name, points, kind, cyclic=False):
    obj = poly_curve(name, points, cyclic=cyclic)
    obj.worldpaint_waterfall.kind = kind
    return obj


def cliff_scene():
    x, y = np.meshgrid(CELL * np.arange(NX), CELL * np.arange(NY))
    terrain = grid_terrain("Terrain", (0.0, 0.0), CELL, cliff_height(x, y))
    bpy.context.scene.worldpaint.terrain = terrain
    upstream = np.array([[20.0, 100.0], [70.0, 100.0], [118.0, 100.0]])
    curve("Stream", np.column_stack([upstream, cliff_height(upstream[:, 0], upstream[:, 1])]), 'CONTACT')
    lip = np.array([118.0, 100.0, float(cliff_height(118.0, 100.0))])
    curve("Fall", np.array([lip, [136.0, 100.0, POOL[3]]]), 'FREE_FALL')
    a = np.linspace(0.0, 2.0 * np.pi, 24, endpoint=False)
    ring = np.column_stack([POOL[0] + POOL[2] * np.cos(a), POOL[1] + POOL[2] * np.sin(a), np.full(len(a), POOL[3])])
    curve("Pool", ring, 'POOL', cyclic=True)
    downstream = np.array([[150.0, 100.0], [220.0, 102.0], [290.0, 100.0]])
    z = np.minimum(cliff_height(downstream[:, 0], downstream[:, 1]), POOL[3])
    z[0] = POOL[3]
    curve("River", np.column_stack([downstream, z]), 'CONTACT')
    return terrain


def water_objects():
    collection = bpy.data.collections.get("Water")
    return [o for o in collection.objects if o.get("wp_water")] if collection is not None else []


def attribute(mesh, name):
    values = np.empty(len(mesh.vertices), dtype=np.float64 if mesh.attributes[name].data_type == 'FLOAT' else np.int64)
    mesh.attributes[name].data.foreach_get("value", values)
    return values


def triangles_of(mesh):
    loops = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", loops)
    return loops.reshape(-1, 3)


def in_triangles(xy, vertices, triangles):
    """Whether each point (N, 2) lies in one of the triangles (T, 3) of the vertices (V, 2)."""
    a, b, c = (vertices[triangles[:, k]][None] for k in range(3))
    p = xy[:, None, :]

    def side(u, v, w):
        return (v[..., 0] - u[..., 0]) * (w[..., 1] - u[..., 1]) - (v[..., 1] - u[..., 1]) * (w[..., 0] - u[..., 0])

    d1, d2, d3 = side(p, a, b), side(p, b, c), side(p, c, a)
    inside = ~(((d1 < 0) | (d2 < 0) | (d3 < 0)) & ((d1 > 0) | (d2 > 0) | (d3 > 0)))
    return inside.any(axis=1)


def test_a_cliff_network_gets_water_meshes_a_deformed_terrain_and_undo_removes_them():
    terrain = cliff_scene()
    before = evaluated_vertices(terrain)
    bpy.ops.ed.undo_push(message="scene drawn")
    assert bpy.ops.worldpaint.build_waterfall(seed=1) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="Build Waterfall")
    terrain = bpy.data.objects["Terrain"]
    assert KEY in terrain.data.shape_keys.key_blocks
    after = evaluated_vertices(terrain)
    change = np.abs(after - before).max(axis=1)
    print(f"terrain: {np.count_nonzero(change > 1e-3)} of {len(change)} vertices moved, up to {change.max():.2f} m")
    assert change.max() > 0.1, "the terrain adapts to the water"
    far = np.hypot(before[:, 0] - 150.0, before[:, 1] - 100.0) > 180.0
    assert change[far].max() < 1e-3, "far from the water the terrain stays"

    (water,) = water_objects()
    mesh = water.data
    assert len(mesh.polygons) > 0
    for name in ("speed", "foam", "rocks", "disturbance", "invalid", "part"):
        assert name in mesh.attributes, name
    foam = attribute(mesh, "foam")
    assert 0.0 <= foam.min() and foam.max() <= 1.0 and foam.max() > 0.0
    assert water.material_slots[0].material.name == "WorldPaint Water"

    # the riverbed lies under the water surface where the water touches the ground (the valley's river)
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    import worldpaint_engine as engine
    from worldpaint.bridge.terrain import mesh_arrays

    vertices, triangles = mesh_arrays(terrain, bpy.context.evaluated_depsgraph_get())
    ground = engine.Terrain(vertices, triangles).heights_at(np.ascontiguousarray(co[:, :2]))
    # on the valley's river, the axis (where the water flows) lies over the riverbed, and the banks (where it
    # stands still) rise back to the water's level
    river = (co[:, 0] > 160.0) & (co[:, 0] < 280.0) & (attribute(mesh, "part") == 0)
    axis = river & (attribute(mesh, "speed") > 0.0)
    banks = river & (attribute(mesh, "speed") == 0.0)
    depth = co[axis, 2] - ground[axis]
    # two cells beyond each bank, away from the nearest axis point (the bank vertex itself lies between a riverbed
    # node and a bank node of the grid)
    a, b = co[axis], co[banks]
    nearest = a[np.argmin(((b[:, None, :2] - a[None, :, :2]) ** 2).sum(axis=2), axis=1)]
    out = b[:, :2] - nearest[:, :2]
    out /= np.maximum(np.linalg.norm(out, axis=1, keepdims=True), 1e-9)
    beyond = np.ascontiguousarray(b[:, :2] + 2.0 * CELL * out)
    # in the bends of a meandering river a cell beyond one bank may lie in the water of the next bend: only dry
    # ground counts
    dry = ~in_triangles(beyond, co[:, :2], triangles_of(mesh))
    rise = engine.Terrain(vertices, triangles).heights_at(beyond[dry]) - b[dry, 2]
    print(f"river: {axis.sum()} axis points, water depth {depth.min():.2f}..{depth.max():.2f} m; dry ground two "
          f"cells beyond {dry.sum()} bank points: {rise.min():.2f}..{rise.max():.2f} m against the water")
    assert axis.sum() > 10 and depth.min() > 0.0
    risen = np.mean(rise > -0.1)
    print(f"{risen:.0%} of them within 0.1 m of the water's level or above it")
    # the rest lie a few tenths below, in the bends of the meandering river, where the ground a ring out takes the
    # level of the nearest water, a little downstream
    assert dry.sum() > 10 and risen >= 0.9 and np.median(rise) > 0.1

    # rocks along the riverbed, in the water, instanced and snapped onto the terrain, turned and scaled as synthesized
    rocks = rock_cloud()
    assert len(rocks.data.vertices) > 0 and rocks.modifiers
    from worldpaint.bridge.instances import point_cloud_arrays

    rock_co, rotation, scale, _ = point_cloud_arrays(rocks)
    again = engine_waterfall(rock_co[:, :2])
    on_mesh = in_triangles(np.ascontiguousarray(rock_co[:, :2]), co[:, :2], triangles_of(mesh))
    print(f"{len(rock_co)} river rocks, {again['is_water'].sum()} in the water, {on_mesh.sum()} on the water mesh; "
          f"rotations {rotation.min():.2f}..{rotation.max():.2f}, scales {scale.min():.2f}..{scale.max():.2f}")
    # the water's edge is read between grid nodes: a rock may stand a little past the mesh's bank
    assert again["is_water"].all() and on_mesh.mean() > 0.95
    # where they stand: the heights are the terrain mesh's (the cloud is snapped onto it), not the engine's grid's
    assert np.allclose(again["rocks"][:, :2], rock_co[:, :2], atol=1e-3), "the same seed gives the same rocks"
    assert rotation.max() > 0.0 and scale.min() < scale.max()

    bpy.ops.ed.undo()
    terrain = bpy.data.objects["Terrain"]
    assert terrain.data.shape_keys is None or KEY not in terrain.data.shape_keys.key_blocks
    assert not water_objects()
    assert not any(o.get("wp_points") == "River rock" for o in bpy.data.objects)


def rock_cloud():
    return next(o for o in bpy.data.objects if o.get("wp_points") == "River rock")


def engine_waterfall(points, rock_color=None, seed=1):
    """The engine's waterfall of the scene's controllers, as Build Waterfall computes it, read at ``points`` (N, 2):
    its ``is_water`` there is where the water stands."""
    import worldpaint_engine as engine
    from worldpaint.bridge import terrain, terrain_edit

    obj = bpy.data.objects["Terrain"]
    settings = bpy.context.scene.worldpaint.terrain_edit
    controllers = terrain_edit.waterfall_controllers(bpy.context, None)
    with terrain_edit.without_key(obj, terrain_edit.WATERFALL_KEY):
        heightfield = terrain.engine_terrain(bpy.context, obj)
    return engine.build_waterfall(heightfield, controllers, np.ascontiguousarray(points, dtype=np.float64), seed,
                                  min_slope=settings.min_slope, overhang=settings.overhang, falloff=settings.falloff,
                                  max_width=settings.max_width, rock_color=rock_color)


def closest_pair(xy):
    d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
    np.fill_diagonal(d, np.inf)
    return d.min()


def test_rocks_from_a_learned_palette_color_stand_in_the_water_with_its_spacing():
    cliff_scene()
    # boulders placed by hand on the plateau, at least 3 m apart, learned as a palette color
    prototypes()
    examples = hard_core_examples("Rock", (20.0, 130.0), 50.0, 0.04, 3.0, seed=2)
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Boulders", region_mode='RECT', rect_min=(20.0, 130.0),
                                          rect_max=(70.0, 180.0)) == {'FINISHED'}
    import worldpaint_engine as engine

    boulders = bpy.context.scene.worldpaint.palette["Boulders"]
    (learned,) = engine.color_summary(boulders.json)["categories"]
    bpy.context.scene.worldpaint.terrain_edit.rock_color = "Boulders"
    bpy.ops.ed.undo_push(message="color learned")
    assert bpy.ops.worldpaint.build_waterfall(seed=1) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="Build Waterfall")
    from worldpaint.bridge.instances import point_cloud_arrays

    rocks, _, _, _ = point_cloud_arrays(rock_cloud())
    again = engine_waterfall(rocks[:, :2], rock_color=boulders.json)
    closest = closest_pair(rocks[:, :2])
    print(f"{len(examples)} boulders learned ({learned['density']:.4f} per m², at least "
          f"{learned['min_distance']:.2f} m apart): {len(rocks)} rocks, {again['is_water'].sum()} in the water, "
          f"closest two {closest:.2f} m")
    assert len(rocks) >= 5 and again["is_water"].all()
    assert np.allclose(again["rocks"][:, :2], rocks[:, :2], atol=1e-3), "the rocks are the learned color's"
    assert closest >= learned["min_distance"] - 1e-3 and closest >= 3.0
    builtin = engine_waterfall(rocks[:, :2])["rocks"]
    print(f"the built-in river rocks instead: {len(builtin)}, closest two {closest_pair(builtin[:, :2]):.2f} m")
    assert closest_pair(builtin[:, :2]) < 3.0

    # undo takes the rocks away and keeps the color
    bpy.ops.ed.undo()
    assert not any(o.get("wp_points") == "River rock" for o in bpy.data.objects)
    assert "Boulders" in bpy.context.scene.worldpaint.palette


def test_an_unknown_rock_color_is_reported_and_nothing_changes():
    terrain = cliff_scene()
    bpy.context.scene.worldpaint.terrain_edit.rock_color = "Pebbles"
    with pytest.raises(RuntimeError, match="No color named 'Pebbles'"):
        bpy.ops.worldpaint.build_waterfall()
    assert terrain.data.shape_keys is None and not water_objects()
    assert not any(o.get("wp_points") == "River rock" for o in bpy.data.objects)


def test_a_rock_color_that_is_not_a_color_is_an_engine_error():
    cliff_scene()
    import worldpaint_engine as engine

    with pytest.raises(engine.InputError, match="rock_color is not a color"):
        engine_waterfall(np.zeros((0, 2)), rock_color="{not json")
    bpy.context.scene.worldpaint.palette.add().name = "Broken"
    bpy.context.scene.worldpaint.terrain_edit.rock_color = "Broken"
    with pytest.raises(RuntimeError, match="rock_color is not a color"):
        bpy.ops.worldpaint.build_waterfall()
    terrain = bpy.data.objects["Terrain"]
    assert terrain.data.shape_keys is None and not water_objects()


def test_instances_in_the_water_are_removed_and_the_others_stay_on_the_ground():
    cliff_scene()
    from worldpaint.bridge.instances import point_cloud_arrays
    from worldpaint.bridge.points import point_cloud_object, write_points

    # trees every 4 m over the valley, across the river's path
    x, y = np.meshgrid(np.arange(160.0, 280.0, 4.0), np.arange(70.0, 130.0, 4.0))
    xy = np.column_stack([x.ravel(), y.ravel()])
    trees = point_cloud_object(bpy.context.scene, "Tree")
    n = len(xy)
    write_points(trees, np.column_stack([xy, cliff_height(xy[:, 0], xy[:, 1])]), np.zeros(n), np.ones(n),
                 np.zeros(n, dtype=np.int32))
    assert bpy.ops.worldpaint.build_waterfall(seed=1) == {'FINISHED'}
    (water,) = water_objects()
    co = np.empty(len(water.data.vertices) * 3)
    water.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    left, _, _, _ = point_cloud_arrays(trees)
    wet = in_triangles(np.ascontiguousarray(left[:, :2]), co[:, :2], triangles_of(water.data))
    print(f"trees: {n} before, {len(left)} after, {wet.sum()} of those on the water mesh")
    assert len(left) < n, "the trees in the river are gone"
    assert wet.mean() < 0.02
    # the others moved with the ground under them (read bilinearly on the terrain's grid, as the engine reads it)
    import worldpaint_engine as engine

    heights = evaluated_vertices(bpy.data.objects["Terrain"])[:, 2].reshape(NY, NX)
    ground = engine.Terrain.from_grid((0.0, 0.0), CELL, heights).heights_at(np.ascontiguousarray(left[:, :2]))
    error = np.abs(left[:, 2] - ground)
    print(f"trees off the ground: at most {error.max() * 100:.2f} cm")
    assert error.max() < 0.02


def test_segments_outside_their_range_are_marked_on_the_water():
    cliff_scene()
    # a "free-fall" drawn along the gentle plateau: its slope is a stream's, not a fall's
    run = np.array([[30.0, 40.0], [60.0, 40.0]])
    curve("Gentle fall", np.column_stack([run, cliff_height(run[:, 0], run[:, 1])]), 'FREE_FALL')
    assert bpy.ops.worldpaint.build_waterfall(seed=1) == {'FINISHED'}
    (water,) = water_objects()
    invalid, part = attribute(water.data, "invalid"), attribute(water.data, "part")
    co = np.empty(len(water.data.vertices) * 3)
    water.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    gentle = (part == 1) & (co[:, 0] < 70.0) & (np.abs(co[:, 1] - 40.0) < 20.0)
    print(f"{int(invalid.sum())} of {len(invalid)} water vertices marked invalid, {gentle.sum()} on the gentle fall")
    assert gentle.any() and (invalid[gentle] == 1.0).all()
    assert set(np.unique(invalid)) <= {0.0, 1.0} and invalid[part == 2].max() == 0.0
    assert invalid[part == 0].max() == 0.0, "the streams and the river keep within their types' ranges"


def ribbon_widths(mesh):
    """Bank-to-bank width of every row of the contact ribbons (rows of left bank, axis, right bank vertices)."""
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    rows = co.reshape(-1, 3)[attribute(mesh, "part") == 0].reshape(-1, 3, 3)
    return np.linalg.norm(rows[:, 0, :2] - rows[:, 2, :2], axis=1)


def test_the_widest_water_setting_bounds_the_rivers():
    cliff_scene()
    assert bpy.ops.worldpaint.build_waterfall(seed=1) == {'FINISHED'}
    wide = ribbon_widths(water_objects()[0].data).max()
    bpy.context.scene.worldpaint.terrain_edit.max_width = 6.0
    assert bpy.ops.worldpaint.build_waterfall(seed=1) == {'FINISHED'}
    narrow = ribbon_widths(water_objects()[0].data)
    print(f"widest ribbon {wide:.1f} m by the section model, {narrow.max():.1f} m with Widest Water at 6 m")
    assert wide > 8.0 and narrow.max() <= 6.0 + 1e-4 and narrow.min() > 0.0


def test_no_controller_is_reported_and_nothing_changes():
    x, y = np.meshgrid(CELL * np.arange(NX), CELL * np.arange(NY))
    terrain = grid_terrain("Terrain", (0.0, 0.0), CELL, cliff_height(x, y))
    bpy.context.scene.worldpaint.terrain = terrain
    with pytest.raises(RuntimeError, match="No waterfall controller"):
        bpy.ops.worldpaint.build_waterfall()
    assert terrain.data.shape_keys is None and not water_objects()


def small_stream():
    """A 1 m stream on the plateau: a little water, no room for a river rock."""
    points = np.array([[20.0, 100.0], [21.0, 100.0]])
    return curve("Brook", np.column_stack([points, cliff_height(points[:, 0], points[:, 1])]), 'CONTACT')


def test_a_waterfall_without_rocks_leaves_no_empty_rock_cloud_prototype_or_material():
    x, y = np.meshgrid(CELL * np.arange(NX), CELL * np.arange(NY))
    grid_terrain("Terrain", (0.0, 0.0), CELL, cliff_height(x, y))
    bpy.context.scene.worldpaint.terrain = bpy.data.objects["Terrain"]
    small_stream()
    assert bpy.ops.worldpaint.build_waterfall(seed=1) == {'FINISHED'}
    assert len(water_objects()) == 1
    assert not any(o.get("wp_points") == "River rock" for o in bpy.data.objects)
    assert "River rock" not in bpy.data.meshes and "WP_proto_River rock" not in bpy.data.collections
    assert "WorldPaint Rock" not in bpy.data.materials and not bpy.data.node_groups


def test_a_waterfall_without_rocks_replaces_the_rocks_of_the_one_before():
    cliff_scene()
    assert bpy.ops.worldpaint.build_waterfall(seed=1) == {'FINISHED'}
    assert len(rock_cloud().data.vertices) > 0
    for obj in bpy.data.objects:
        if obj.type == 'CURVE':
            obj.worldpaint_waterfall.kind = 'NONE'
    small_stream()
    assert bpy.ops.worldpaint.build_waterfall(seed=1) == {'FINISHED'}
    assert len(water_objects()) == 1
    assert not any(o.get("wp_points") == "River rock" for o in bpy.data.objects)


def test_controller_roles_survive_save_and_reload(tmp_path):
    cliff_scene()
    bpy.data.objects["Pool"].worldpaint_waterfall.strength = 3.0
    path = str(tmp_path / "waterfall.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    roles = {o.name: o.worldpaint_waterfall.kind for o in bpy.data.objects if o.type == 'CURVE'}
    assert roles == {"Stream": 'CONTACT', "Fall": 'FREE_FALL', "Pool": 'POOL', "River": 'CONTACT'}
    assert bpy.data.objects["Pool"].worldpaint_waterfall.strength == 3.0
