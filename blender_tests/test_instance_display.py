"""Instances at scale: they keep their heights between terrain changes (the instancer casts no ray), every change of
the terrain (an Embed Roads, vertices moved by hand) puts them back on the new surface once, and each category's
viewport display (a share, boxes, cones, a camera distance) shows what it says while a render shows everything; the
settings and the snapped heights survive saving and loading, and a file of the ray-casting instancer is upgraded."""

import bpy
import numpy as np
import pytest
from scene_kit import grid_terrain, irregular_terrain, poly_curve, prototypes
from worldpaint.bridge import points, snap
from worldpaint.bridge.instances import point_cloud_objects

N = 4000


def instance_positions(obj, depsgraph=None):
    """World XYZ (M, 3) of the instances the cloud ``obj`` shows in ``depsgraph`` (default: the viewport's)."""
    depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
    found = [tuple(i.matrix_world.translation) for i in depsgraph.object_instances
             if i.is_instance and i.parent is not None and i.parent.original == obj]
    return np.array(found, dtype=np.float64).reshape(-1, 3)


def surface_heights(terrain, xy):
    """The evaluated terrain's height under each XY (a ray from above, as Blender casts it)."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    out = []
    for x, y in xy:
        hit, where, *_ = terrain.ray_cast((x, y, 1000.0), (0.0, 0.0, -1.0), depsgraph=depsgraph)
        out.append(where.z if hit else np.nan)
    return np.array(out)


def painted_cloud(terrain, n=N, extent=(2.0, 98.0), seed=1):
    """A "Tree" cloud of ``n`` points at height 0 over the terrain, with its instancer standing on ``terrain``."""
    prototypes()
    rng = np.random.default_rng(seed)
    xy = rng.uniform(extent[0], extent[1], (n, 2))
    obj = points.point_cloud_object(bpy.context.scene, "Tree")
    points.write_points(obj, np.column_stack([xy, np.zeros(n)]), rng.uniform(0.0, 6.0, n), np.ones(n),
                        np.zeros(n, dtype=np.int32))
    points.set_instancer(obj, bpy.data.collections["Tree"], terrain)
    snap.snap_clouds(bpy.context.scene, [obj], terrain)
    return obj


def test_an_instance_keeps_its_height_until_the_terrain_changes_then_stands_on_the_new_surface():
    terrain = irregular_terrain()
    obj = painted_cloud(terrain)
    group = obj.modifiers["WorldPaint"].node_group
    assert not [n for n in group.nodes if n.bl_idname == 'GeometryNodeRaycast'], "the instancer casts no ray"
    shown = instance_positions(obj)
    assert len(shown) == N
    assert np.abs(shown[:, 2] - surface_heights(terrain, shown[:, :2])).max() < 0.01

    # a point lifted 5 m above the ground stays there, evaluation after evaluation, while the terrain is unchanged
    co = np.empty(N * 3, dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    lifted = co[0].copy()
    co[0, 2] += 5.0
    obj.data.vertices.foreach_set("co", co.ravel())
    obj.data.update()
    for _ in range(2):
        bpy.context.view_layer.update()
        at = instance_positions(obj)
        k = np.argmin(np.linalg.norm(at[:, :2] - lifted[:2], axis=1))
        assert at[k, 2] == pytest.approx(lifted[2] + 5.0, abs=1e-4)

    # the terrain rises by a bump of up to 3 m: every instance, the lifted one too, stands on the new surface
    mesh = terrain.data
    ground = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", ground)
    ground = ground.reshape(-1, 3)
    ground[:, 2] += 3.0 * np.exp(-((ground[:, 0] - 50.0) ** 2 + (ground[:, 1] - 50.0) ** 2) / 400.0)
    mesh.vertices.foreach_set("co", ground.ravel())
    mesh.update()
    bpy.context.view_layer.update()
    shown = instance_positions(obj)
    error = np.abs(shown[:, 2] - surface_heights(terrain, shown[:, :2]))
    print(f"after the bump: worst height error {error.max() * 1000:.2f} mm over {len(shown)} instances")
    assert error.max() < 0.01
    k = np.argmin(np.linalg.norm(shown[:, :2] - lifted[:2], axis=1))
    assert abs(shown[k, 2] - lifted[2]) < 3.01 and shown[k, 2] < lifted[2] + 4.0, "the lifted one came down"


def test_a_new_terrain_is_binned_once_for_the_clouds_put_on_it(monkeypatch):
    built = []
    make = snap.Surface.__init__

    def counted(surface, *args):
        built.append(surface)
        make(surface, *args)

    monkeypatch.setattr(snap.Surface, "__init__", counted)
    terrain = irregular_terrain()
    # the first evaluation of the new terrain reports its geometry as changed: its mesh is the one just binned
    obj = painted_cloud(terrain)
    bpy.context.view_layer.update()
    assert len(built) == 1, "the terrain was binned, and its clouds snapped, a second time"
    shown = instance_positions(obj)
    assert np.abs(shown[:, 2] - surface_heights(terrain, shown[:, :2])).max() < 0.01
    # a vertex moved by hand (the vertex count and the object's place unchanged) is a new surface
    mesh = terrain.data
    mesh.vertices[len(mesh.vertices) // 2].co.z += 2.0
    mesh.update()
    bpy.context.view_layer.update()
    assert len(built) == 2


def test_embed_roads_puts_the_instances_on_the_cut_and_filled_ground():
    size, cell = 120.0, 2.0
    n = int(size / cell) + 1
    x, y = np.meshgrid(cell * np.arange(n), cell * np.arange(n))
    terrain = grid_terrain("Terrain", (0.0, 0.0), cell, 0.2 * y + np.sin(x / 9.0))
    scene = bpy.context.scene
    scene.worldpaint.terrain = terrain
    obj = painted_cloud(terrain, extent=(10.0, 110.0))
    before = instance_positions(obj)
    roads = bpy.data.collections.new("Roads")
    scene.collection.children.link(roads)
    poly_curve("Road", np.array([[5.0, 60.0], [115.0, 60.0]]), collection=roads)
    scene.worldpaint.terrain_edit.reseat = False  # only the snap after the change moves the instances
    assert bpy.ops.worldpaint.embed_roads(roads="Roads", width=6.0, bank_width=8.0) == {'FINISHED'}
    bpy.context.view_layer.update()
    after = instance_positions(obj)
    error = np.abs(after[:, 2] - surface_heights(terrain, after[:, :2]))
    same = np.lexsort(before.T[:2]), np.lexsort(after.T[:2])  # an instance keeps its XY
    moved = np.abs(after[same[1], 2] - before[same[0], 2]).max()
    print(f"Embed Roads: instances moved up to {moved:.2f} m, worst height error {error.max() * 1000:.2f} mm")
    assert moved > 0.3, "the road changed the ground under some instances"
    assert error.max() < 0.01


def rendered_instances(obj):
    """The objects instanced on ``obj`` in a render (Cycles, one sample, 8 x 8 pixels, from the scene's camera)."""
    found = []

    def collect(_scene, depsgraph=None):
        if depsgraph is not None and depsgraph.mode == 'RENDER':
            found[:] = [i.object.original for i in depsgraph.object_instances
                        if i.is_instance and i.parent is not None and i.parent.original == obj]

    scene = bpy.context.scene
    scene.render.engine = 'CYCLES'
    scene.cycles.samples = 1
    scene.render.resolution_x = scene.render.resolution_y = 8
    bpy.app.handlers.frame_change_post.append(collect)  # a render evaluates its own depsgraph and calls it
    try:
        bpy.ops.render.render()
    finally:
        bpy.app.handlers.frame_change_post.remove(collect)
    return found


def test_display_percentage_shows_that_share_in_the_viewport_and_every_instance_in_a_render():
    terrain = irregular_terrain()
    obj = painted_cloud(terrain, n=5000)
    assert bpy.ops.worldpaint.instance_display(category="Tree", mode='PERCENTAGE', percentage=10.0) == {'FINISHED'}
    first = instance_positions(obj)
    again = instance_positions(obj)
    print(f"Percentage 10 %: {len(first)} of 5000 shown in the viewport")
    assert 400 <= len(first) <= 600
    assert np.array_equal(first, again), "the same instances on every redraw"

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    bpy.context.scene.collection.objects.link(camera)
    bpy.context.scene.camera = camera
    rendered = rendered_instances(obj)
    print(f"in a render: {len(rendered)} instances")
    assert len(rendered) == 5000


def test_bounds_proxy_and_cull_distance_show_what_they_say():
    terrain = irregular_terrain()
    obj = painted_cloud(terrain, n=300)
    tree = bpy.data.collections["Tree"].objects[0]
    lo, hi = np.array(tree.bound_box).min(axis=0), np.array(tree.bound_box).max(axis=0)
    for mode, faces in (('BOUNDS', 0), ('PROXY', 8)):
        points.set_display(obj, mode=mode)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        stand_ins = [i.object for i in depsgraph.object_instances
                     if i.is_instance and i.parent is not None and i.parent.original == obj]
        assert len(stand_ins) == 300
        mesh = stand_ins[0].data
        co = np.array([v.co for v in mesh.vertices])
        assert len(mesh.polygons) >= faces and (faces or len(mesh.edges) == 12), mode
        # a box of the prototype's bounds; a cone as wide as the wider side, standing on the prototype's base
        assert co[:, 2].min() == pytest.approx(lo[2], abs=1e-4) and co[:, 2].max() == pytest.approx(hi[2], abs=1e-4)
        assert np.abs(co[:, :2]).max() == pytest.approx(np.abs(np.vstack([lo, hi])[:, :2]).max(), abs=1e-3)

    points.set_display(obj, mode='FULL', cull_distance=30.0)
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.location = (50.0, 50.0, 10.0)
    shown = instance_positions(obj)
    distance = np.linalg.norm(shown - camera.location, axis=1)
    co = np.empty(300 * 3, dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    within = (np.linalg.norm(co.reshape(-1, 3) - camera.location, axis=1) <= 30.0).sum()
    print(f"cull distance 30 m: {len(shown)} of 300 shown, {within} within 30 m of the camera")
    assert len(shown) == within > 0 and distance.max() <= 30.0 + 1e-4


def test_a_lod_distance_keeps_full_meshes_near_the_camera_and_stand_ins_beyond_it_and_a_render_has_all_in_full():
    terrain = irregular_terrain()
    obj = painted_cloud(terrain, n=400)
    tree = bpy.data.collections["Tree"].objects[0]
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.location = (20.0, 20.0, 5.0)
    points.set_display(obj, mode='PROXY', cull_distance=90.0, lod_distance=35.0)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    shown = [(i.object.original == tree, tuple(i.matrix_world.translation)) for i in depsgraph.object_instances
             if i.is_instance and i.parent is not None and i.parent.original == obj]
    full = np.array([xyz for is_tree, xyz in shown if is_tree]).reshape(-1, 3)
    cones = np.array([xyz for is_tree, xyz in shown if not is_tree]).reshape(-1, 3)
    co = np.empty(400 * 3, dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    d = np.linalg.norm(co.reshape(-1, 3) - camera.location, axis=1)
    print(f"LOD 35 m, cull 90 m: {len(full)} full, {len(cones)} cones, {(d > 90.0).sum()} hidden of 400")
    assert len(full) == (d <= 35.0).sum() > 0 and len(cones) == ((d > 35.0) & (d <= 90.0)).sum() > 0
    assert np.linalg.norm(full - camera.location, axis=1).max() <= 35.0 + 1e-3
    assert np.linalg.norm(cones - camera.location, axis=1).min() > 35.0 - 1e-3
    # a render has every instance with its full mesh
    rendered = rendered_instances(obj)
    assert len(rendered) == 400 and all(o == tree for o in rendered)


def test_display_settings_and_heights_survive_save_and_reload(tmp_path):
    terrain = irregular_terrain()
    obj = painted_cloud(terrain, n=500)
    points.set_display(obj, mode='PERCENTAGE', percentage=25.0, cull_distance=80.0, lod_distance=40.0)
    shown = len(instance_positions(obj))
    path = str(tmp_path / "display.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    obj = point_cloud_objects(bpy.context.scene)["Tree"]
    assert points.display(obj) == ('PERCENTAGE', 25.0, 80.0, 40.0)
    assert len(instance_positions(obj)) == shown


def test_a_file_of_the_ray_casting_instancer_loads_with_its_instances_on_the_terrain(tmp_path):
    terrain = irregular_terrain()
    obj = painted_cloud(terrain, n=500)
    # as an older file has them: the points at the engine's heights (here 2 m off), the instancer of version 1
    co = np.empty(500 * 3, dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    co[2::3] += 2.0
    obj.data.vertices.foreach_set("co", co)
    obj.data.update()
    obj.modifiers["WorldPaint"].node_group["wp_version"] = 1
    path = str(tmp_path / "older.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    obj = point_cloud_objects(bpy.context.scene)["Tree"]
    terrain = bpy.data.objects["Irregular"]
    assert obj.modifiers["WorldPaint"].node_group["wp_version"] == points.INSTANCER_VERSION
    shown = instance_positions(obj)
    assert len(shown) == 500
    assert np.abs(shown[:, 2] - surface_heights(terrain, shown[:, :2])).max() < 0.01
