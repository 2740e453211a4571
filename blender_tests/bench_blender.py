"""Blender-side benchmark (``make bench``): building 100k synthesized instances, Blender's own Poisson disk, and
the painting tools end to end.

1. A 3-category color (uniform, clustered, hard-core; 0.1 instances per m² in all) is pasted over a 1 km² terrain
   through the Paste Color operator; reported: engine synthesis, building the point clouds and instancer, the
   whole operator (a second paste, and the first, which also bins the new terrain's triangles for the snap), and
   evaluating the Geometry Nodes instancer.
2. On the same terrain, Geometry Nodes' Distribute Points on Faces (Poisson disk) makes as many points as the
   clustered category; its evaluation time and its fidelity to the clustered exemplar (density ratio, rdf L2 via the
   engine's compare) are reported beside the engine's.
3. A 40-dab brush stroke (radius 20 m, one tree per 25 m², among ~12,000 existing trees) as the viewport tool runs
   it: per dab, the engine's dab plus the point-cloud update; median and worst dab. Then the same stroke through the
   headless operator, and one step of dragging a 5,000-tree region (engine move plus the cloud update).

4. Model variety: a 501-face tree cut into three parts with ten edits each (1,000 possible trees); Generate Variants
   makes all 1,000 (asking #V enumerates them): the engine's assembly and self-intersection check, then building
   the 1,000 meshes in Blender (timed alone, and the whole operator).

5. Millions: 100k and then 1,000,000 instances (uniform, in the 3 categories, at the engine's terrain heights) on the
   1 km² terrain: building the point clouds and instancers, evaluating the instancers with the terrain unchanged in
   each display mode (Full, Percentage 10 %, Bounds, Proxy), and after a change of the terrain mesh the update that
   re-snaps every cloud (the snap alone, and the whole depsgraph update with the instancers), side by side.

6. Real places: File › Import › WorldPaint Place on the OpenStreetMap layers and SRTM tiles of ``../shared/data/real``
   beside the project (Bayreuth, Andorra; Kirchberg's two layers without terrain): the engine's import alone, then the
   whole operator (the engine, building the scene, and the first evaluation of the roads' ribbons), against the
   issue's bound of 30 s each.

Usage: python blender_tests/bench_blender.py [--size 1000] [--only millions | --only variety | --only place]
"""

import argparse
import pathlib
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "addon"))
sys.path.insert(0, str(ROOT / "assets"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402
import worldpaint  # noqa: E402
import worldpaint_engine as engine  # noqa: E402
from scene_kit import (  # noqa: E402
    collection_instances,
    edited_part,
    engine_terrain_object,
    prototypes,
    segmented_tree,
    select_only,
    tilt_ring,
)
from worldpaint.bridge import engine as facade  # noqa: E402
from worldpaint.bridge import engine_place, snap, variety  # noqa: E402
from worldpaint.bridge import points as wp_points  # noqa: E402
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects  # noqa: E402
from worldpaint.ops.common import SceneContent  # noqa: E402

EXEMPLAR = {"shape": "rect", "min": [0.0, 0.0], "max": [100.0, 100.0]}
CATEGORIES = [
    {"name": "Tree", "layer": "vegetation", "kind": "distribution", "priority": 0},
    {"name": "Rock", "layer": "vegetation", "kind": "distribution", "priority": 1},
    {"name": "Grass", "layer": "vegetation", "kind": "distribution", "priority": 2},
]


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def best_of(runs, fn):
    """The result of ``fn`` and its shortest time over ``runs`` calls (the first also starts thread pools)."""
    times = []
    for _ in range(runs):
        out, elapsed = timed(fn)
        times.append(elapsed)
    return out, min(times)


def exemplar_color():
    """Trees hard-core, rocks uniform, grass clustered: 0.1 per m² together."""
    trees = facade.exemplar_hard_core(EXEMPLAR, 0.03, 3.0, 1)
    rocks = facade.exemplar_uniform(EXEMPLAR, 0.03, 2)
    grass = facade.exemplar_clustered(EXEMPLAR, 0.004, 10.0, 2.0, 3)
    xy = np.concatenate([trees, rocks, grass])
    index = np.repeat(np.arange(3, dtype=np.int32), [len(trees), len(rocks), len(grass)])
    color = engine.learn_color(engine.Scene(None, CATEGORIES, xy, index), EXEMPLAR, "Bench")
    grass_only = engine.learn_color(engine.Scene(None, [CATEGORIES[2]], grass, np.zeros(len(grass), np.int32)),
                                    EXEMPLAR, "Grass")
    return color, grass_only, len(grass) / 1e4


def poisson_disk_points(terrain_obj, count, distance_min):
    """Points of Geometry Nodes' Distribute Points on Faces (Poisson disk) on the terrain, and the evaluation time."""
    group = bpy.data.node_groups.new("Bench Distribute", 'GeometryNodeTree')
    group.interface.new_socket("Geometry", in_out='INPUT', socket_type='NodeSocketGeometry')
    group.interface.new_socket("Geometry", in_out='OUTPUT', socket_type='NodeSocketGeometry')
    gin, gout = group.nodes.new('NodeGroupInput'), group.nodes.new('NodeGroupOutput')
    dist = group.nodes.new('GeometryNodeDistributePointsOnFaces')
    dist.distribute_method = 'POISSON'
    to_verts = group.nodes.new('GeometryNodePointsToVertices')
    group.links.new(gin.outputs["Geometry"], dist.inputs["Mesh"])
    group.links.new(dist.outputs["Points"], to_verts.inputs["Points"])
    group.links.new(to_verts.outputs["Mesh"], gout.inputs["Geometry"])
    dist.inputs["Distance Min"].default_value = distance_min
    obj = terrain_obj.copy()
    obj.data = terrain_obj.data.copy()
    bpy.context.scene.collection.objects.link(obj)
    mod = obj.modifiers.new("Distribute", 'NODES')
    mod.node_group = group
    area = sum(p.area for p in obj.data.polygons)
    density = count / area

    def evaluate():
        obj.update_tag()
        depsgraph = bpy.context.evaluated_depsgraph_get()  # evaluates what was tagged
        evaluated = obj.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        co = np.empty(len(mesh.vertices) * 3, np.float32)
        mesh.vertices.foreach_get("co", co)
        evaluated.to_mesh_clear()
        return co

    for _ in range(3):  # Poisson disk rejection lowers the count: correct the maximum density
        dist.inputs["Density Max"].default_value = density
        co = evaluate()
        got = len(co) // 3
        if abs(got - count) <= 0.02 * count:
            break
        density *= count / max(got, 1)
    co, elapsed = best_of(3, evaluate)  # timed as the engine is
    return co.reshape(-1, 3)[:, :2].astype(np.float64), elapsed


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=float, default=1000.0, help="terrain side in metres")
    parser.add_argument("--only", choices=["millions"], help="run only this section")
    args = parser.parse_args()
    worldpaint.register()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    prototypes()
    terrain = facade.exemplar_demo_terrain(args.size, 2.0, 7)
    terrain_obj = engine_terrain_object("Terrain", terrain)
    scene = bpy.context.scene
    scene.worldpaint.terrain = terrain_obj
    color, grass_color, grass_density = exemplar_color()
    entry = scene.worldpaint.palette.add()
    entry.name, entry.json = "Bench", color
    whole = {"shape": "rect", "min": [0.0, 0.0], "max": [args.size, args.size]}

    no = np.zeros((0, 2))
    empty = engine.Scene(terrain, CATEGORIES, no, np.zeros(0, np.int32))
    result, t_engine = best_of(3, lambda: engine.synthesize(empty, color, whole, 1))
    n = len(result["positions"])

    def build():
        for index, category in enumerate(result["categories"]):
            m = result["category_index"] == index
            obj = wp_points.point_cloud_object(scene, category["name"])
            co = np.column_stack([result["positions"][m], result["heights"][m]])
            wp_points.write_points(obj, co, result["rotations"][m], result["scales"][m], result["prototype"][m])
            wp_points.set_instancer(obj, bpy.data.collections[category["name"]], terrain_obj)

    _, t_build = timed(build)
    for obj in list(point_cloud_objects(scene).values()):
        wp_points.remove_object(obj)
    # the first paste on a new terrain also evaluates it and bins its triangles for the snap (kept until it changes)
    _, t_first = timed(lambda: bpy.ops.worldpaint.paste_color(
        seed=1, region_mode='RECT', rect_min=(0.0, 0.0), rect_max=(args.size, args.size)))
    _, t_operator = timed(lambda: bpy.ops.worldpaint.paste_color(
        seed=2, region_mode='RECT', rect_min=(0.0, 0.0), rect_max=(args.size, args.size)))
    n_op = sum(len(o.data.vertices) for o in point_cloud_objects(scene).values())
    for obj in point_cloud_objects(scene).values():
        obj.update_tag()
    depsgraph, t_eval = timed(bpy.context.evaluated_depsgraph_get)
    instances = sum(1 for i in depsgraph.object_instances if i.is_instance)

    # the engine and Blender's Poisson disk at the clustered category's count
    grass_engine = point_cloud_arrays(point_cloud_objects(scene)["Grass"])[0][:, :2]
    count = len(grass_engine)
    gn_xy, t_gn = poisson_disk_points(terrain_obj, count, 0.3)
    one = [{"name": "Grass"}]

    def fidelity(xy):
        scene = engine.Scene(None, one, np.ascontiguousarray(xy), np.zeros(len(xy), np.int32))
        learned = engine.learn_color(scene, whole, "x")
        f = engine.compare(grass_color, learned)
        return f["density_ratio"]["Grass"], f["max_rdf_l2"]

    (ratio_engine, rdf_engine), (ratio_gn, rdf_gn) = fidelity(grass_engine), fidelity(gn_xy)
    # the reference: a second independent draw of the clustered process, on the exemplar's own area
    second = facade.exemplar_clustered(EXEMPLAR, 0.004, 10.0, 2.0, 99)
    learned_second = engine.learn_color(engine.Scene(None, one, second, np.zeros(len(second), np.int32)), EXEMPLAR,
                                        "second")
    rdf_second = engine.compare(grass_color, learned_second)["max_rdf_l2"]

    print(f"terrain {args.size:.0f} m x {args.size:.0f} m ({len(terrain_obj.data.vertices)} vertices)")
    print(f"engine synthesis          {n:7d} instances, 3 categories  {t_engine:7.3f} s   (best of 3, as GN's)")
    print(f"build point clouds + GN   {n:7d} instances               {t_build:7.3f} s   (target <= 0.5 s)")
    print(f"Paste Color operator      {n_op:7d} instances               {t_operator:7.3f} s   (extract+engine+build; "
          f"the first on a new terrain {t_first:.3f} s)")
    print(f"evaluate GN instancer     {instances:7d} instances               {t_eval:7.3f} s")
    print(f"GN Distribute (Poisson)   {len(gn_xy):7d} points                  {t_gn:7.3f} s")
    per_engine, per_gn = t_engine / max(n, 1), t_gn / max(len(gn_xy), 1)
    print(f"per point: engine {per_engine * 1e6:.2f} us, GN Poisson disk {per_gn * 1e6:.2f} us, "
          f"engine / GN {per_engine / per_gn:.1f}")
    print(f"clustered fidelity  engine: density ratio {ratio_engine:.3f}, rdf L2 {rdf_engine:.3f}")
    print(f"clustered fidelity  GN Poisson disk: density ratio {ratio_gn:.3f}, rdf L2 {rdf_gn:.3f}")
    print(f"clustered reference (second draw of the process): rdf L2 {rdf_second:.3f}")


def bench_painting():
    """Section 3 of the module documentation."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    prototypes()
    terrain = facade.exemplar_demo_terrain(600.0, 2.0, 7)
    terrain_obj = engine_terrain_object("Terrain", terrain)
    scene = bpy.context.scene
    scene.worldpaint.terrain = terrain_obj
    corner = {"shape": "rect", "min": [0.0, 0.0], "max": [100.0, 100.0]}
    xy = facade.exemplar_hard_core(corner, 0.04, 3.0, 1)
    examples = collection_instances("Tree", xy, terrain.heights_at(xy))
    select_only(examples)
    bpy.ops.worldpaint.learn_color(name="Trees", region_mode='RECT', rect_min=(0.0, 0.0), rect_max=(100.0, 100.0))
    for obj in examples:
        bpy.data.objects.remove(obj)
    select_only([])
    # existing trees on both sides of a 60 m corridor along y = 300, where the brush goes
    for rect in (((0.0, 0.0), (600.0, 270.0)), ((0.0, 330.0), (600.0, 600.0))):
        bpy.ops.worldpaint.paste_color(seed=2, region_mode='RECT', rect_min=rect[0], rect_max=rect[1])
    existing = len(point_cloud_objects(scene)["Tree"].data.vertices)
    path = np.column_stack([np.linspace(100.0, 490.0, 40), np.full(40, 300.0)])

    content = SceneContent(bpy.context)
    stroke = facade.paint_stroke(content.engine_scene(), color=scene.worldpaint.palette["Trees"].json, radius=20.0,
                                 spacing=0.5, opacity=1.0, falloff="constant", seed=1, influence_radius=None)
    dabs = []
    for p in path:
        t0 = time.perf_counter()
        stroke.follow(np.array([p]))
        content.apply(bpy.context, stroke.edit())
        dabs.append(time.perf_counter() - t0)
    painted = len(stroke.edit().positions)
    content.restore(bpy.context)
    points = [{"name": "", "location": (x, y, 0.0)} for x, y in path]
    _, t_stroke = timed(lambda: bpy.ops.worldpaint.brush(stroke=points, radius=20.0, seed=1))

    # one step of a drag: a 375 m square of ~5,000 trees, 5 m to the east, written back to the cloud
    bpy.ops.worldpaint.clear_region(region_mode='RECT', rect_min=(0.0, 0.0), rect_max=(600.0, 600.0))
    square = {"shape": "rect", "min": [110.0, 110.0], "max": [465.0, 465.0]}
    bpy.ops.worldpaint.paste_color(seed=3, region_mode='RECT', rect_min=square["min"], rect_max=square["max"])
    content = SceneContent(bpy.context)
    color = scene.worldpaint.palette["Trees"].json
    steps = []
    for k in range(5):
        t0 = time.perf_counter()
        moved = facade.move_region(content.engine_scene(), color=color, source=square,
                                   offset=(5.0 * (k + 1), 0.0), seed=1, influence_radius=None)
        content.restore(bpy.context)
        content.apply(bpy.context, moved.edit)
        steps.append(time.perf_counter() - t0)

    ms = np.array(dabs) * 1e3
    print(f"brush stroke, 40 dabs r = 20 m among {existing} trees: {painted} trees painted")
    print(f"  per dab (engine dab + cloud update): median {np.median(ms):.1f} ms, worst {ms.max():.1f} ms "
          "(target <= 30 ms)")
    print(f"  the same stroke through the Brush operator (headless): {t_stroke:.3f} s")
    print(f"move one drag step of {moved.moved} trees (engine + cloud update): median "
          f"{np.median(steps) * 1e3:.1f} ms, worst {max(steps) * 1e3:.1f} ms (target <= 100 ms)")


def bench_variety():
    """Section 4 of the module documentation."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    tree = segmented_tree(sides=125)
    bpy.context.view_layer.objects.active = tree
    bpy.ops.worldpaint.decompose_model(source='ATTRIBUTE', attribute="part", root=0)
    for k in range(1, 10):
        for label, above in ((0, 1.5), (1, 3.0)):
            tilt_ring(edited_part(tree, label, f"lean {label}.{k}"), above, 0.02 * k, 'X' if k % 2 else 'Y')
        crown = edited_part(tree, 2, f"crown {k}")
        max(crown.data.vertices, key=lambda v: v.co.z).co.z += 0.15 * k
    operator = bpy.ops.worldpaint.generate_variants
    _, t_all = timed(lambda: operator(count=1000, seed=1))
    settings = tree.worldpaint_variety
    variants = list(settings.generated.objects)
    model = variety_model(tree)
    result, t_engine = timed(lambda: engine.generate_variants(model["model"], model["labels"], model["variants"],
                                                              1000, 1, root=0))
    materials = [slot.material for slot in tree.material_slots]
    built = bpy.data.collections.new("Built again")
    _, t_meshes = timed(lambda: variety.write_variants(built, "again", result["models"], materials))
    print(f"variety: {len(tree.data.polygons)}-face tree, {settings.total} possible; {len(variants)} generated "
          f"({settings.report.split(';')[0]})")
    print(f"generate variants (engine)   {t_engine:7.3f} s")
    print(f"build {len(result['models'])} variant meshes     {t_meshes:7.3f} s   (target <= 1 s)")
    print(f"Generate Variants operator   {t_all:7.3f} s   (read parts + engine + build {len(variants)} meshes)")


def variety_model(tree):
    """What Generate Variants hands the engine, read again: the model, its labels and the parts' edits."""
    labels = variety.face_labels(tree, 'ATTRIBUTE', "part")
    model = variety.mesh_model(tree.data)
    found = engine.decompose_model(model, labels, 0)
    edits = []
    for label, piece in zip(found["labels"], found["components"], strict=True):
        collection = tree.worldpaint_variety.parts.children[f"{tree.name} part {label}"]
        edits.append([variety.variant_model(o, piece) for o in collection.objects
                      if o != collection[variety.PART_TAG]])
    return {"model": model, "labels": labels, "variants": edits}


def bench_millions(size, counts=(100_000, 1_000_000)):
    """Section 5 of the module documentation; one column per count."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    prototypes()
    terrain = facade.exemplar_demo_terrain(size, 2.0, 7)
    terrain_obj = engine_terrain_object("Terrain", terrain)
    scene = bpy.context.scene
    scene.worldpaint.terrain = terrain_obj
    bpy.context.view_layer.update()
    rows = {}

    def row(name, value):
        rows.setdefault(name, []).append(value)

    for n in counts:
        for obj in list(point_cloud_objects(scene).values()):
            wp_points.remove_object(obj)
        bpy.context.view_layer.update()
        rng = np.random.default_rng(n)
        xy = rng.uniform(0.0, size, (n, 2))
        co = np.column_stack([xy, terrain.heights_at(xy)])
        which = rng.integers(0, len(CATEGORIES), n)
        columns = [(c["name"], co[which == k]) for k, c in enumerate(CATEGORIES)]

        def build(columns=columns, rng=rng):
            for name, part in columns:
                obj = wp_points.point_cloud_object(scene, name)
                wp_points.write_points(obj, part, rng.uniform(0.0, 6.3, len(part)), rng.uniform(0.8, 1.2, len(part)),
                                       np.zeros(len(part), np.int32))
                wp_points.set_instancer(obj, bpy.data.collections[name], terrain_obj)

        row("build point clouds + instancers", timed(build)[1])
        clouds = list(point_cloud_objects(scene).values())
        bpy.context.view_layer.update()  # the first evaluation of new objects
        for mode, _label, _ in wp_points.DISPLAY_MODES:
            for obj in clouds:
                wp_points.set_display(obj, mode=mode, percentage=10.0)
            bpy.context.view_layer.update()
            for obj in clouds:
                obj.update_tag()
            row(f"evaluate instancers, {mode.lower()}", timed(bpy.context.view_layer.update)[1])
        # distance LOD: full meshes within 150 m of a camera in the middle, cones to 400 m, nothing beyond
        camera = scene.camera or bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
        if scene.camera is None:
            scene.collection.objects.link(camera)
            scene.camera = camera
        camera.location = (size / 2.0, size / 2.0, 50.0)
        for obj in clouds:
            wp_points.set_display(obj, mode='PROXY', cull_distance=400.0, lod_distance=150.0)
        bpy.context.view_layer.update()
        for obj in clouds:
            obj.update_tag()
        row("evaluate instancers, proxy LOD 150 m, cull 400", timed(bpy.context.view_layer.update)[1])
        for obj in clouds:
            wp_points.set_display(obj, mode='FULL', cull_distance=0.0, lod_distance=0.0)
        bpy.context.view_layer.update()
        row("re-snap alone (read terrain, bin, look up)", timed(lambda: snap.snap_scene(scene))[1])
        mesh = terrain_obj.data
        ground = np.empty(len(mesh.vertices) * 3, np.float32)
        mesh.vertices.foreach_get("co", ground)
        ground[2::3] += 0.5 * np.sin(ground[0::3] / 40.0)  # a change under every instance
        mesh.vertices.foreach_set("co", ground)
        mesh.update()
        row("terrain changed: update (re-snap + instancers)", timed(bpy.context.view_layer.update)[1])
    print(f"millions: terrain {size:.0f} m x {size:.0f} m ({len(terrain_obj.data.vertices)} vertices, "
          f"{len(terrain_obj.data.polygons) * 2} triangles)")
    print(f"{'':48s}" + "".join(f"{n:>12,d}" for n in counts))
    for name, values in rows.items():
        print(f"{name:48s}" + "".join(f"{v:10.3f} s" for v in values))
    print("targets at 1M: build <= 0.5 s, evaluation without terrain change <= 0.3 s")


REAL_DATA = ROOT.parent / "shared" / "data" / "real"
PLACES = (  # (name, map layers, elevation model)
    ("north_bayreuth", ("buildings", "roads", "areas", "places"), "north_bayreuth_srtm3.asc"),
    ("andorra", ("buildings", "roads", "areas", "places"), "andorra_srtm3.asc"),
    ("kirchberg_iller", ("buildings", "roads"), None),
)


def bench_place():
    """Section 6 of the module documentation."""
    for stem, names, dem_name in PLACES:
        layers = [REAL_DATA / "villages" / f"{stem}_{name}.geojson" for name in names]
        dem = REAL_DATA / "terrain" / dem_name if dem_name else None
        missing = [str(f) for f in [*layers, dem] if f is not None and not f.is_file()]
        if missing:
            print(f"place {stem}: skipped, {missing[0]} not found")
            continue
        bpy.ops.wm.read_factory_settings(use_empty=True)
        paths, elevation = [str(f) for f in layers], "" if dem is None else str(dem)
        imported, t_engine = timed(lambda p=paths, e=elevation: engine_place.import_place(p, e or None))
        _, t_operator = timed(lambda p=paths, e=elevation: bpy.ops.worldpaint.import_place(layers=";".join(p),
                                                                                           elevation=e))
        roads = sum(float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) for p in imported.roads.points)
        grid = "" if imported.terrain is None else " x ".join(map(str, imported.terrain.heights.shape[::-1]))
        print(f"place {stem:16s} {len(imported.buildings.type):5d} buildings, {roads / 1000:6.1f} km of roads, "
              f"{len(imported.areas.kind):5d} areas{', terrain ' + grid if grid else ''}: engine {t_engine:6.2f} s, "
              f"Import WorldPaint Place operator {t_operator:6.2f} s   (bound 30 s)")


if __name__ == "__main__":
    only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else None
    if only == "millions":
        worldpaint.register()
        bench_millions(1000.0)
    elif only == "variety":
        worldpaint.register()
        bench_variety()
    elif only == "place":
        worldpaint.register()
        bench_place()
    else:
        main()
        bench_painting()
        bench_variety()
        bench_millions(1000.0)
        bench_place()
