"""The demo (``make demo``): learn colors from hand-made-looking exemplars and paint them over a larger terrain.

1. A small exemplar terrain with ridges carries trees only on its 20-35 degree slopes, rocks, and grass clustered
   around the rocks; Learn Color turns it into the color "Slope forest".
2. A grove of clumped trees on flat ground becomes the color "Grove".
3. A village of streets (a hand-drawn curve) and houses along them becomes the color "Village".
4. All three are pasted over a 600 m terrain of hills the examples never saw: the forest keeps to the slopes it
   liked, the grove keeps its clumps, the village grows streets draped on the hills with houses along them, and each
   paste blends with what is around it.
5. A highland hamlet grows by its growth scenario (thesis ch. 3) in a clearing of the forest in the foreground: a
   church, houses and farms with doors and windows, on parcels beside roads that wind up the hills; Embed Roads
   cuts its roads into the slope.
6. A stream drawn down the steepest slope from the hamlet becomes a waterfall scene (thesis ch. 4): it falls into a
   pool where the hills are steepest and leaves it as a river; Build Waterfall classifies its segments, lays the water
   over it, carves its bed and the pool into the terrain and scatters rocks along it.
7. A block of vines planted by hand in rows becomes the arrangement "Vineyard" (Ijiri et al. 2008); pasted into a
   clearing of the forest, its rows grow along the hillside's contour lines, drawn as two flow curves.
8. In a scene of its own, three mountain silhouettes are sketched over a camera's view of other, wooded hills (thesis
   ch. 5); Apply Sketch deforms the terrain until, seen from that camera, its silhouettes follow the strokes, and
   carries the trees with the ground.

The forest's trees are 36 variants of one low-poly tree (Maréchal et al.): cut into three parts, each part edited
into a few copies, assembled into every combination; each painted tree shows the variant least used around it. The
variety picture shows birches made the same way from the low-poly birch (``assets/birch.obj``): decomposed by its
materials, two edited copies of each of its six parts (``scene_kit.birch_variants``), 729 different trees.

The scene is then dressed for Cycles (``showcase.py``: a sky and a sun, materials made by code, land around the
terrain to the horizon) and rendered on the CPU, few samples denoised: OUT/demo.png (the whole scene), one picture
per system (OUT/demo_forest.png, demo_village.png, demo_waterfall.png, demo_vineyard.png, demo_variants.png) and
the sketch before and after (OUT/sketch_before.png with the strokes drawn over it, sketch_after.png).
OUT/demo.blend holds the scene with a camera per picture. ``--only variants`` makes and renders the variety picture
alone, on a meadow of its own (a quick look at it without the rest of the demo).

``--only place`` imports a real place through File › Import › WorldPaint Place, the countryside north of Bayreuth
(its OpenStreetMap buildings, roads and land-use areas, and its SRTM terrain, from ``../shared/data/real`` beside the
project), and renders the village of Neudrossenfeld from above at an angle: OUT/demo_place.png; then learns a color
over the village and pastes it over gentle hills far from the place: OUT/demo_place_learned.png shows both side by
side.

``--only village`` imports Andorra the same way, learns a village type from Encamp with Learn Village and grows a
village like it on steep hills far from the place: OUT/demo_village_like.png shows the real village and the grown one
side by side.

``--only world`` paints a world of 10 x 10 km of Andorra's SRTM model from a map of five colors with three villages
joined by roads (``blender_tests/bench_world_painted.py``'s world, filled on a LocalCluster of threads), loads it with
Load World Tiles (as cones beyond 1.5 km of the camera in the viewport, full nearer; a render shows every instance in
full) and renders it from above (OUT/demo_world.png) and from the road into a village (OUT/demo_world_inside.png).
Usage: python assets/demo.py [--out out] [--samples 16] [--percent 100] [--only variants|place|village|world]
"""

import argparse
import pathlib
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "addon"))
sys.path.insert(0, str(ROOT / "assets"))

import bpy  # noqa: E402, I001 (bpy first: it provides bmesh)
import bmesh  # noqa: E402
import numpy as np  # noqa: E402
import showcase  # noqa: E402
import worldpaint  # noqa: E402
from mathutils import Matrix, Vector  # noqa: E402
from scene_kit import (  # noqa: E402
    SKETCH_CELL,
    SKETCH_N,
    birch_variants,
    collection_instances,
    draw_strokes,
    engine_terrain_object,
    evaluated_vertices,
    grid_terrain,
    hills_height,
    import_birch,
    mesh_object,
    poly_curve,
    segmented_tree,
    select_only,
    sketch_scene,
    slope_exemplar,
    three_strokes,
    tree_variants,
    village_exemplar,
    vineyard_reference,
)
from worldpaint.bridge import engine, engine_place, place, points, variety  # noqa: E402
from worldpaint.bridge.curves import structure_objects  # noqa: E402
from worldpaint.bridge.instances import point_cloud_objects  # noqa: E402
from worldpaint.bridge.sketch import sketch_collection  # noqa: E402

HILLS_SIZE = 600.0
GROVE_REGION = {"shape": "rect", "min": [-220.0, -150.0], "max": [-120.0, -50.0]}
VILLAGE_ORIGIN = (-1000.0, 0.0)
VILLAGE_SIZE = 300.0
VILLAGE_DESTINATION = ((210.0, 460.0), (470.0, 670.0))
HAMLET_CENTER = (360.0, 360.0)
HAMLET_RADIUS = 90.0
STREAM_START = (340.0, 330.0)
VINEYARD_CENTER = (235.0, 255.0)
VINEYARD_RADIUS = 45.0


def run(op, **kwargs):
    """Runs an operator and stops the demo with its message if it fails."""
    result = op(**kwargs)
    if result != {'FINISHED'}:
        sys.exit(f"{op.idname_py()} returned {result}")


def build_and_learn():
    # the slope exemplar: its own small terrain, examples in its [0, 100]^2 corner
    exemplar_terrain, examples, _ = slope_exemplar(size=200.0, exemplar=100.0, seed=1)
    exemplar_terrain.location.x = -220.0
    for obj in examples:
        obj.location.x -= 220.0
    bpy.context.view_layer.update()
    select_only(examples)
    run(bpy.ops.worldpaint.learn_color, name="Slope forest", terrain=exemplar_terrain.name, region_mode='RECT',
        rect_min=(-220.0, 0.0), rect_max=(-120.0, 100.0))

    # the hills everything is painted on
    hills = engine_terrain_object("Hills", engine.exemplar_demo_terrain(HILLS_SIZE, 2.0, 11))

    # the grove: Thomas-process clumps of trees on a flat patch beside the exemplar
    flat = engine.terrain_from_grid((-230.0, -160.0), 2.0, np.zeros((61, 61)))
    ground = engine_terrain_object("Grove ground", flat)
    xy = engine.exemplar_clustered(GROVE_REGION, 0.0015, 9.0, 3.0, 5)
    rng = np.random.default_rng(5)
    grove = collection_instances("Tree", xy, np.zeros(len(xy)), rng.uniform(0, 2 * np.pi, len(xy)),
                                 rng.uniform(0.7, 1.1, len(xy)))
    bpy.context.view_layer.update()
    select_only(grove)
    run(bpy.ops.worldpaint.learn_color, name="Grove", terrain=ground.name, region_mode='RECT',
        rect_min=tuple(GROVE_REGION["min"]), rect_max=tuple(GROVE_REGION["max"]))

    # the village: streets drawn as one curve, houses along them, on its own valley side
    x0, y0 = VILLAGE_ORIGIN
    village_ground, roads, houses, _ = village_exemplar(
        size=VILLAGE_SIZE, origin=VILLAGE_ORIGIN, extent=(x0 - 100.0, y0 - 100.0, x0 + 400.0, y0 + 400.0)
    )
    village_ground.name = "Village ground"
    select_only([roads, *houses])
    run(bpy.ops.worldpaint.learn_color, name="Village", terrain=village_ground.name, region_mode='RECT',
        rect_min=VILLAGE_ORIGIN, rect_max=(x0 + VILLAGE_SIZE, y0 + VILLAGE_SIZE))
    out_of_pictures([exemplar_terrain, *examples, ground, *grove, village_ground, roads, *houses])
    return hills


def out_of_pictures(objects):
    """The exemplars stay in the file beside the hills but out of the renders, where the land around the hills
    would run through them."""
    for obj in objects:
        obj.hide_render = True


def vary_trees():
    """36 variants of a low-poly tree, made off the painted area, that the forest's trees then show."""
    tree = segmented_tree("Tree model")
    showcase.bark_and_leaves(tree)
    tree.location = (-600.0, -300.0, 0.0)
    bpy.context.view_layer.objects.active = tree
    run(bpy.ops.worldpaint.decompose_model, object=tree.name, source='ATTRIBUTE', attribute="part", root=0)
    tree_variants(tree)
    run(bpy.ops.worldpaint.generate_variants, object=tree.name, count=36, seed=1)
    settings = tree.worldpaint_variety
    bpy.context.scene.worldpaint.categories["Tree"].variants = settings.generated
    variety.hide_collection(bpy.context.scene, settings.parts)
    tree.hide_render = tree.hide_viewport = True
    print(f"tree variants: {settings.report}")
    return settings.generated


# the birches the variety picture shows, as the copy each of the six parts takes (0 its original piece, 1 and 2 its
# two edited copies): every two of them differ in every part
BIRCH_PICKS = [[(k + shift * c) % 3 for c in range(6)] for shift in (0, 1) for k in range(3)]


def vary_birches():
    """Every variant of the low-poly birch (729), and the birches of ``BIRCH_PICKS`` assembled by hand for the variety
    picture: white bark on the trunk and branches, leaves on the leaf masses (the six material slots it is decomposed
    by share two materials). Returns the picked birches' objects."""
    tree = import_birch()
    bark = bpy.data.materials.get("Birch bark") or bpy.data.materials.new("Birch bark")
    leaves = bpy.data.materials.get("Birch leaves") or bpy.data.materials.new("Birch leaves")
    old = [slot.material for slot in tree.material_slots]
    for k, slot in enumerate(tree.material_slots):
        slot.material = bark if k < 3 else leaves
    for material in old:
        if material is not None and material.users == 0:
            bpy.data.materials.remove(material)
    bpy.context.view_layer.objects.active = tree
    run(bpy.ops.worldpaint.decompose_model, object=tree.name, source='MATERIALS', root=0)
    birch_variants(tree)
    run(bpy.ops.worldpaint.generate_variants, object=tree.name, count=1000, seed=1)
    settings = tree.worldpaint_variety
    print(f"birch variants: {settings.report}")
    picked = []
    for picks in BIRCH_PICKS:
        for item, pick in zip(settings.components, picks, strict=True):
            collection = settings.parts.children[f"{tree.name} part {item.label}"]
            copies = sorted((o for o in collection.objects if o != collection["wp_part"]), key=lambda o: o.name)
            item.pick = copies[pick - 1] if pick else None
        before = set(settings.generated.objects)
        run(bpy.ops.worldpaint.generate_variants, object=tree.name, by_hand=True)
        picked.extend(set(settings.generated.objects) - before)
    variety.hide_collection(bpy.context.scene, settings.parts)
    tree.hide_render = tree.hide_viewport = True
    return picked


def paint(hills):
    select_only([])
    bpy.context.scene.worldpaint.terrain = hills
    run(bpy.ops.worldpaint.paste_color, color="Slope forest", terrain=hills.name, seed=1, region_mode='RECT',
        rect_min=(0.0, 0.0), rect_max=(HILLS_SIZE, HILLS_SIZE))
    run(bpy.ops.worldpaint.paste_color, color="Grove", terrain=hills.name, seed=2, region_mode='CIRCLE',
        circle_center=(150.0, 450.0), circle_radius=110.0)
    (x0, y0), (x1, y1) = VILLAGE_DESTINATION
    run(bpy.ops.worldpaint.paste_color, color="Village", terrain=hills.name, seed=3, region_mode='RECT',
        rect_min=(x0, y0), rect_max=(x1, y1))
    road = structure_objects(bpy.context.scene)["road"]
    road.data.materials.append(bpy.data.materials.new("Road"))  # shaded by showcase


def grow_hamlet(hills):
    """A highland hamlet in a clearing cut into the painted forest, inside a closed curve beside the other content."""
    a = np.linspace(0.0, 2.0 * np.pi, 48, endpoint=False)
    xy = np.column_stack([HAMLET_CENTER[0] + HAMLET_RADIUS * np.cos(a), HAMLET_CENTER[1] + HAMLET_RADIUS * np.sin(a)])
    region = poly_curve("Hamlet region", xy, cyclic=True)
    run(bpy.ops.worldpaint.clear_region, terrain=hills.name, region_mode='CURVE', curve=region.name)
    settings = bpy.context.scene.worldpaint.village
    settings.region = region
    run(bpy.ops.worldpaint.load_village_preset, preset="highland_hamlet")
    run(bpy.ops.worldpaint.generate_village, terrain=hills.name, seed=3)
    print(f"hamlet: {settings.report}")
    # its roads cut into the slope: level carriageways with banks, the houses re-seated
    for obj in bpy.context.selected_objects:
        obj.select_set(False)
    run(bpy.ops.worldpaint.embed_roads, terrain=hills.name, width=5.0, bank_width=6.0)


def stream_path(terrain, start, length=240.0, step=4.0):
    """Points down the steepest slope from ``start`` (XY), one every ``step`` metres, stopping in a hollow."""
    path = [np.asarray(start, dtype=np.float64)]
    for _ in range(int(length / step)):
        p = path[-1]
        around = p + step * np.array([[np.cos(a), np.sin(a)] for a in np.linspace(0.0, 2.0 * np.pi, 16,
                                                                                    endpoint=False)])
        heights = terrain.heights_at(np.ascontiguousarray(around))
        best = int(np.nanargmin(heights))
        if not heights[best] < terrain.heights_at(p[None])[0] - 0.05:
            break
        path.append(around[best])
    xy = np.array(path)
    return np.column_stack([xy, terrain.heights_at(np.ascontiguousarray(xy))])


def build_waterfall(hills):
    """A stream running down the hills; where they are steepest it falls into a pool dug below the lip, and a river
    leaves the pool. The terrain is carved under all of it."""
    path = stream_path(engine.exemplar_demo_terrain(HILLS_SIZE, 2.0, 11), STREAM_START)
    run_ahead = 5  # steps of the path (4 m each) from the lip to where the river meets the ground again
    drop = path[:-run_ahead, 2] - path[run_ahead:, 2]
    lip = int(np.argmax(drop))
    level = float(path[lip + run_ahead, 2])
    ahead = path[lip + 1, :2] - path[lip, :2]
    ahead /= np.linalg.norm(ahead)
    radius = 5.0
    centre = path[lip, :2] + (radius + 2.0) * ahead  # a plunge pool dug into the slope below the lip
    foot = centre - 0.6 * radius * ahead
    poly_curve("Stream", path[:lip + 1][::-3][::-1]).worldpaint_waterfall.kind = 'CONTACT'
    poly_curve("Fall", np.array([path[lip], [*foot, level]])).worldpaint_waterfall.kind = 'FREE_FALL'
    a = np.linspace(0.0, 2.0 * np.pi, 24, endpoint=False)
    ring = np.column_stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a), np.full(len(a), level)])
    poly_curve("Pool", ring, cyclic=True).worldpaint_waterfall.kind = 'POOL'
    out = path[lip + run_ahead, :2] - centre
    leaving = centre + radius * out / np.linalg.norm(out)
    river = np.vstack([[*leaving, level], path[lip + run_ahead + 1:][::3]])
    river[:, 2] = np.minimum(river[:, 2], level)
    poly_curve("River", river).worldpaint_waterfall.kind = 'CONTACT'
    # the river leaves the pool through a cut in the slope, where the section model would widen it to a lake
    bpy.context.scene.worldpaint.terrain_edit.max_width = 6.0
    run(bpy.ops.worldpaint.build_waterfall, terrain=hills.name, seed=1)
    print(f"waterfall: a {drop[lip]:.1f} m fall into a pool of {radius:.1f} m, {len(path)} path points")
    return path[lip], ahead


def plant_vineyard(hills):
    """A vineyard learned from a hand-planted block on flat ground, pasted into a clearing of the forest with its rows
    along the hillside: the flow curves follow the contour line through the clearing's centre."""
    ground = engine_terrain_object("Vine ground", engine.terrain_from_grid((-420.0, -320.0), 2.0, np.zeros((21, 21))))
    vines = vineyard_reference((-410.0, -310.0))
    out_of_pictures([ground, *vines])
    bpy.context.view_layer.update()
    select_only(vines)
    run(bpy.ops.worldpaint.learn_arrangement, name="Vineyard", terrain=ground.name, region_mode='RECT',
        rect_min=(-411.0, -311.0), rect_max=(-395.0, -296.5))
    select_only([])
    run(bpy.ops.worldpaint.pattern_settings, rotation='FLOW', rotation_noise=0.05)
    terrain = engine.exemplar_demo_terrain(HILLS_SIZE, 2.0, 11)
    centre = np.asarray(VINEYARD_CENTER)
    steps = (np.array([2.0, 0.0]), np.array([0.0, 2.0]))
    gradient = np.array([np.subtract(*terrain.heights_at(np.ascontiguousarray([centre + d, centre - d])))
                         for d in steps])
    along = np.array([-gradient[1], gradient[0]]) / np.linalg.norm(gradient)
    flow = bpy.data.collections.new("Vineyard flow")
    bpy.context.scene.collection.children.link(flow)
    for k, offset in enumerate((-0.6, 0.6)):
        middle = centre + offset * VINEYARD_RADIUS * np.array([-along[1], along[0]])
        ends = np.array([middle - 1.2 * VINEYARD_RADIUS * along, middle + 1.2 * VINEYARD_RADIUS * along])
        poly_curve(f"Row flow {k}", np.column_stack([ends, terrain.heights_at(np.ascontiguousarray(ends))]),
                   collection=flow)
    flow.hide_render = True
    run(bpy.ops.worldpaint.clear_region, terrain=hills.name, region_mode='CIRCLE', circle_center=VINEYARD_CENTER,
        circle_radius=VINEYARD_RADIUS + 3.0)
    run(bpy.ops.worldpaint.paste_color, color="Vineyard", terrain=hills.name, seed=4, region_mode='CIRCLE',
        circle_center=VINEYARD_CENTER, circle_radius=VINEYARD_RADIUS, flow=flow.name)


def dress(hills):
    """The look of the pictures: smooth terrain, land to the horizon and materials (the sky and the sun are set per
    picture)."""
    showcase.smooth(hills)
    grid = engine.exemplar_demo_terrain(HILLS_SIZE, 2.0, 11).grid()
    showcase.backdrop("Land around", grid["origin"], grid["cell"], grid["heights"])
    untouched = showcase.dress_materials()
    if untouched:
        print(f"materials left as they were: {', '.join(untouched)}")


def ground_at(x, y):
    return float(engine.exemplar_demo_terrain(HILLS_SIZE, 2.0, 11).heights_at(np.array([[x, y]]))[0])


def cameras(fall):
    """A camera per picture: (file name, camera, resolution). ``fall`` is the waterfall's lip and the direction it
    falls towards."""
    lip, ahead = fall
    x, y = VINEYARD_CENTER
    vineyard = Vector((x, y, ground_at(x, y)))
    pool = Vector((lip[0], lip[1], lip[2] - 8.0))
    front = pool + Vector((*(40.0 * ahead - 25.0 * np.array([ahead[1], -ahead[0]])), 8.0))  # downstream, aside
    views = [  # the sun's azimuth (degrees from north) is turned for a picture whose slope would be in shadow
        # the whole scene from the south-east: the hamlet, the pasted village behind it, the forest on the slopes
        ("demo", (560.0, 170.0, 110.0), (300.0, 430.0, 30.0), 26.0, (1152, 648), showcase.SUN_AZIMUTH),
        # the forest on the slopes from the south-west, the grove's clumps beyond
        ("demo_forest", (60.0, -20.0, 70.0), (180.0, 200.0, 0.0), 30.0, (800, 450), showcase.SUN_AZIMUTH),
        # the hamlet's church, houses and farms on their parcels, the pasted village above them
        ("demo_village", (470.0, 250.0, 85.0), (370.0, 365.0, 15.0), 32.0, (800, 450), showcase.SUN_AZIMUTH),
        # the fall, its pool and the cliff it has cut, the hamlet's church above, from down the valley
        ("demo_waterfall", tuple(front), tuple(pool + Vector((0.0, 0.0, 3.0))), 26.0, (800, 450),
         showcase.SUN_AZIMUTH),
        # the vineyard's rows on the north-facing hillside, from the valley below
        ("demo_vineyard", tuple(vineyard + Vector((25.0, 115.0, 50.0))), tuple(vineyard), 35.0, (800, 450), 330.0),
    ]
    return [(name, showcase.camera(f"Camera {name}", location, target, lens), resolution, azimuth)
            for name, location, target, lens, resolution, azimuth in views]


def variants_stage(shown, meadow_material):
    """The birch variants ``shown`` (objects) in a row on a meadow far from the hills (``meadow_material``), and the
    camera looking at them from the side; returns the stage's collection (to remove afterwards) and the camera."""
    scene = bpy.context.scene
    stage = bpy.data.collections.new("Variant showcase")
    scene.collection.children.link(stage)
    x0, y0, spacing = -900.0, -900.0, 7.0
    for k, source in enumerate(shown):
        obj = bpy.data.objects.new(f"showcase {k}", source.data)
        obj.location = (x0 + spacing * k, y0, 0.0)
        obj.rotation_euler.z = 0.5
        stage.objects.link(obj)
    # a meadow to the horizon: one quad, the air hides its edge 20 km away
    meadow = mesh_object("Meadow", [(x0 - 2e4, y0 - 2e4, 0.0), (x0 + 2e4, y0 - 2e4, 0.0),
                                             (x0 + 2e4, y0 + 2e4, 0.0), (x0 - 2e4, y0 + 2e4, 0.0)], [(0, 1, 2, 3)])
    meadow.data.materials.append(meadow_material)
    scene.collection.objects.unlink(meadow)
    stage.objects.link(meadow)
    middle = x0 + spacing * (len(shown) - 1) / 2.0
    cam = showcase.camera("Camera demo_variants", (middle, y0 - 58.0, 3.0), (middle, y0, 6.0), 50.0)
    return stage, cam


def render_variants(out, birches, meadow_material, percent=100):
    """Renders the variety picture (the land around the hills, if any, hidden); returns its (name, seconds, size)."""
    scene = bpy.context.scene
    land = bpy.data.objects.get("Land around")
    if land is not None:
        land.hide_render = True
    showcase.sky(scene)
    showcase.sun(scene)
    stage, cam = variants_stage(birches, meadow_material)
    size = (1200, 500)
    seconds = showcase.render(scene, cam, out / "demo_variants.png", tuple(side * percent // 100 for side in size))
    for obj in list(stage.objects):
        bpy.data.objects.remove(obj)
    bpy.data.collections.remove(stage)
    if land is not None:
        land.hide_render = False
    return ("demo_variants", seconds, size)


def render_all(out, fall, birches, percent=100):
    """Renders every picture (``birches``: the variants the variety picture shows); returns (name, seconds,
    resolution) of each."""
    scene = bpy.context.scene
    report = []
    for name, cam, (w, h), azimuth in cameras(fall):
        showcase.sky(scene, azimuth=azimuth)
        showcase.sun(scene, azimuth=azimuth)
        seconds = showcase.render(scene, cam, out / f"{name}.png", (w * percent // 100, h * percent // 100))
        report.append((name, seconds, (w, h)))
    report.append(render_variants(out, birches, bpy.data.objects["Hills"].data.materials[0], percent))
    return report


def land_around(terrain):
    """A plain around the sketch's terrain, from the heights of its edge as shown (shape keys applied)."""
    heights = evaluated_vertices(terrain)[:, 2].reshape(SKETCH_N, SKETCH_N)
    land = showcase.backdrop(f"Land around {terrain.name}", (0.0, 0.0), SKETCH_CELL, heights, relief=0.0)
    showcase.far_land(land.data.materials[0])
    return land


def sketch_forest(scene, terrain, trees, count=2500, seed=8):
    """Trees scattered over the sketch's hills beyond the camera's foreground, shown by the instancer as ``trees``
    (the demo's variants): Apply Sketch carries them with the ground it moves."""
    rng = np.random.default_rng(seed)
    xy = rng.uniform((0.0, 40.0), (SKETCH_CELL * (SKETCH_N - 1), 480.0), (count, 2))
    cloud = points.point_cloud_object(scene, "Tree")
    points.write_points(cloud, np.column_stack([xy, hills_height(xy[:, 0], xy[:, 1])]),
                        rng.uniform(0.0, 2.0 * np.pi, count), rng.uniform(0.8, 1.3, count),
                        rng.integers(0, len(trees.objects), count).astype(np.int32))
    points.set_instancer(cloud, trees, terrain)


def sketch_pictures(out, samples, trees, percent=100):
    """Apply Sketch (thesis ch. 5) in a scene of its own: wooded hills seen from a camera at their southern edge,
    three mountain silhouettes drawn over its view (two of them ending on the first), rendered before with the
    strokes over the picture and after Apply Sketch has raised the terrain, and the trees on it, to meet them."""
    scene = bpy.data.scenes.new("Sketch")
    with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0]):
        terrain, cam = sketch_scene("Sketch hills", "Camera sketch")
        showcase.smooth(terrain)
        showcase.terrain(terrain.data.materials[0])
        land = land_around(terrain)
        sketch_forest(scene, terrain, trees)
        showcase.cycles(scene, samples)
        showcase.sky(scene)
        showcase.sun(scene)
        strokes = three_strokes()
        draw_strokes(strokes)
        scene.worldpaint.sketch.reach = 150.0
        size = (900, 600)
        w, h = (side * percent // 100 for side in size)
        shown = showcase.strokes_in_view(cam, strokes, scene)
        report = [("sketch_before", showcase.render(scene, cam, out / "sketch_before.png", (w, h)), size)]
        bpy.data.objects.remove(shown)
        start = time.perf_counter()
        run(bpy.ops.worldpaint.apply_sketch, terrain=terrain.name, camera=cam.name)
        print(f"sketch: applied in {time.perf_counter() - start:.1f} s")
        sketch_collection(scene).hide_render = True  # the features it used, drawn as curves
        bpy.data.objects.remove(land)
        land_around(terrain)  # from the deformed terrain's edge, which Apply Sketch may have raised
        report.append(("sketch_after", showcase.render(scene, cam, out / "sketch_after.png", (w, h)), size))
    return report


REAL_DATA = ROOT.parent / "shared" / "data" / "real"
PLACE = "north_bayreuth"
PLACE_VILLAGE = "Neudrossenfeld"
# area category: (material, linear colour); the other areas are not drawn (the terrain's grass shows there)
AREA_LOOKS = {
    "Forest": ("Place forest", (0.018, 0.045, 0.012)),
    "Meadow": ("Place meadow", (0.075, 0.14, 0.03)),
    "Farmland": ("Place farmland", (0.20, 0.17, 0.075)),
    "Orchard": ("Place orchard", (0.06, 0.12, 0.025)),
    "Residential area": ("Place gardens", (0.085, 0.12, 0.045)),
    "Farmyard": ("Place farmyard", (0.16, 0.14, 0.10)),
    "Water": ("WorldPaint Water", None),
}
AREA_LIFT = 0.4  # the areas' fills float this far above the terrain, the roads' ribbons above them
LEARNED_SIDE = 800.0  # the square around the village that Learn Color reads
# the other terrain: the demo's hills made gentle (the village learned where the land is nearly flat), far enough
# east that neither the place nor the land drawn around it is in its picture
ELSEWHERE = (80000.0, 0.0)
ELSEWHERE_SIZE = 1200.0
ELSEWHERE_RELIEF = 0.2
LIKE_PLACE = "andorra"  # Learn Village's picture: a village of this place, and one grown like it
LIKE_VILLAGE = "Encamp"
LIKE_SIDE = 1000.0  # the square around the village that Learn Village reads
LIKE_EVALUATIONS = 57  # the search: the start and four generations
LIKE_RELIEF = 1.0  # the other hills: the demo's exemplar terrain this much steeper


def place_files(stem=PLACE):
    """(map layers, elevation model) of a real place; the demo stops saying where it looked when absent."""
    layers = [REAL_DATA / "villages" / f"{stem}_{name}.geojson" for name in ("buildings", "roads", "areas", "places")]
    dem = REAL_DATA / "terrain" / f"{stem}_srtm3.asc"
    missing = [str(f) for f in [*layers, dem] if not f.is_file()]
    if missing:
        sys.exit(f"the real place's files are not there: {', '.join(missing)}")
    return layers, dem


def dress_place(scene, terrain):
    """The imported place for Cycles: materials on its roads and areas (the areas lifted above the terrain, the road
    ribbons above the areas), land to the horizon from its terrain's edge."""
    road_names = {name for name, _ in place.ROAD_CATEGORIES.values()}
    road = bpy.data.materials.get("Road") or bpy.data.materials.new("Road")
    for category, obj in structure_objects(scene).items():
        if category in road_names:
            obj.data.materials.append(road)
        fill = next((o for o in scene.objects if o.get("wp_fill") == category), None)
        if fill is None:
            continue
        look = AREA_LOOKS.get(category)
        fill.hide_render = look is None
        if look is not None:
            name, rgb = look
            material = bpy.data.materials.get(name) or bpy.data.materials.new(name)
            if rgb is not None:
                showcase.plain(material, rgb, 0.9, 0.3, 0.05)
            fill.data.materials.append(material)
            fill.location.z += AREA_LIFT
    lift = bpy.data.node_groups["WorldPaint Profile"].nodes  # the ribbons' lift over what they are draped on
    for node in lift:
        if node.bl_idname == 'ShaderNodeVectorMath' and node.operation == 'ADD' and \
                tuple(node.inputs[1].default_value)[:2] == (0.0, 0.0) and node.inputs[1].default_value[2] > 0.0:
            node.inputs[1].default_value = (0.0, 0.0, AREA_LIFT + 0.3)
    showcase.smooth(terrain)
    showcase.backdrop("Land around the place", *grid_of(terrain), relief=0.3)
    untouched = showcase.dress_materials()
    if untouched:
        print(f"materials left as they were: {', '.join(untouched)}")


def place_picture(out, samples, percent=100):
    """File › Import › WorldPaint Place on the countryside north of Bayreuth, rendered around one of its villages
    (OUT/demo_place.png); then a color learned over the village, pasted on other hills, beside it
    (OUT/demo_place_learned.png: the village left, the paste right). Returns the report lines of both."""
    layers, dem = place_files()
    start = time.perf_counter()
    run(bpy.ops.worldpaint.import_place, layers=";".join(map(str, layers)), elevation=str(dem))
    print(f"place: imported {', '.join(p.name for p in layers)} and {dem.name} in {time.perf_counter() - start:.1f} s")
    scene = bpy.context.scene
    named = engine_place.import_place([str(layers[-1])], origin=place.place_origin(scene)).places
    x, y = named.position[named.name.index(PLACE_VILLAGE)]
    ground = float(engine.terrain_from_grid(*grid_of(scene.worldpaint.terrain)).heights_at(np.array([[x, y]]))[0])
    terrain = scene.worldpaint.terrain
    learn_from_place(scene, (x, y))
    hills = paste_elsewhere(scene)
    dress_place(scene, terrain)
    showcase.smooth(hills)
    showcase.backdrop("Land around the hills", *grid_of(hills), relief=0.3)
    showcase.cycles(scene, samples)
    showcase.sky(scene)
    showcase.sun(scene)
    # from the south-east, 700 m out and 380 m up, the village in the middle, the fields and woods beyond
    cam = showcase.camera("Camera place", (x + 420.0, y - 560.0, ground + 380.0), (x - 40.0, y + 60.0, ground), 30.0)
    cam.data.clip_end = 40000.0
    size = (1152, 648)
    w, h = size[0] * percent // 100, size[1] * percent // 100
    report = [("demo_place", showcase.render(scene, cam, out / "demo_place.png", (w, h)), size)]
    # the paste seen as the village is, and the two side by side
    cx, cy = ELSEWHERE[0] + ELSEWHERE_SIZE / 2, ELSEWHERE[1] + ELSEWHERE_SIZE / 2
    height = float(engine.terrain_from_grid(*grid_of(hills)).heights_at(np.array([[cx, cy]]))[0])
    cam = showcase.camera("Camera paste", (cx + 420.0, cy - 560.0, height + 380.0), (cx - 40.0, cy + 60.0, height),
                          30.0)
    cam.data.clip_end = 30000.0
    seconds = showcase.render(scene, cam, out / "demo_place_pasted.png", (w, h))
    side_by_side(out / "demo_place.png", out / "demo_place_pasted.png", out / "demo_place_learned.png")
    report.append(("demo_place_learned", seconds, (2 * size[0], size[1])))
    return report


def learn_from_place(scene, centre):
    """Learn Color over the square around the village: its building clouds and the roads people drive on."""
    low, high = np.asarray(centre) - LEARNED_SIDE / 2, np.asarray(centre) + LEARNED_SIDE / 2
    buildings = set(place.BUILDING_CATEGORIES.values())
    roads = {name for name, _ in place.ROAD_CATEGORIES.values()}
    select_only([o for c, o in point_cloud_objects(scene).items() if c in buildings]
                + [o for c, o in structure_objects(scene).items() if c in roads])
    start = time.perf_counter()
    run(bpy.ops.worldpaint.learn_color, name=PLACE_VILLAGE, region_mode='RECT', rect_min=tuple(low),
        rect_max=tuple(high))
    color = scene.worldpaint.palette[PLACE_VILLAGE]
    print(f"place: learned {PLACE_VILLAGE} in {time.perf_counter() - start:.1f} s; {color.fidelity_line()}")


def paste_elsewhere(scene):
    """The learned village pasted over gentle hills far from the place; the hills' terrain object."""
    grid = engine.exemplar_demo_terrain(ELSEWHERE_SIZE, 4.0, 11).grid()
    hills = grid_terrain("Elsewhere", ELSEWHERE, grid["cell"], ELSEWHERE_RELIEF * np.asarray(grid["heights"]))
    select_only([])
    scene.worldpaint.terrain = hills
    margin = (ELSEWHERE_SIZE - LEARNED_SIDE) / 2
    start = time.perf_counter()
    run(bpy.ops.worldpaint.paste_color, color=PLACE_VILLAGE, terrain=hills.name, seed=1, region_mode='RECT',
        rect_min=(ELSEWHERE[0] + margin, ELSEWHERE[1] + margin),
        rect_max=(ELSEWHERE[0] + ELSEWHERE_SIZE - margin, ELSEWHERE[1] + ELSEWHERE_SIZE - margin))
    print(f"place: pasted {PLACE_VILLAGE} on other hills in {time.perf_counter() - start:.1f} s")
    return hills


def side_by_side(left, right, path):
    """The PNG ``path``: the pictures ``left`` and ``right`` (of one size) side by side."""
    images = [bpy.data.images.load(str(p)) for p in (left, right)]
    w, h = images[0].size
    pixels = []
    for image in images:
        rgba = np.empty(w * h * 4, dtype=np.float32)
        image.pixels.foreach_get(rgba)
        pixels.append(rgba.reshape(h, w, 4))
        bpy.data.images.remove(image)
    both = bpy.data.images.new("Side by side", 2 * w, h, alpha=True)
    both.pixels.foreach_set(np.concatenate(pixels, axis=1).ravel())
    both.filepath_raw = str(path)
    both.file_format = 'PNG'
    both.save()
    bpy.data.images.remove(both)


def village_like_picture(out, samples, percent=100):
    """Learn Village on Encamp (Andorra, imported), then a village grown like it on steep hills far from the place:
    OUT/demo_village_like.png shows the real village (left) and the grown one (right), seen alike. Returns the report
    line."""
    layers, dem = place_files(LIKE_PLACE)
    run(bpy.ops.worldpaint.import_place, layers=";".join(map(str, layers)), elevation=str(dem))
    scene = bpy.context.scene
    settings = scene.worldpaint.village
    named = engine_place.import_place([str(layers[-1])], origin=place.place_origin(scene)).places
    x, y = named.position[named.name.index(LIKE_VILLAGE)]
    terrain = scene.worldpaint.terrain
    settings.region = square_curve(LIKE_VILLAGE, (x, y), LIKE_SIDE)
    start = time.perf_counter()
    run(bpy.ops.worldpaint.learn_village, minutes=9.0, max_evaluations=LIKE_EVALUATIONS)
    print(f"village: {settings.learn_report} ({time.perf_counter() - start:.0f} s)")
    grid = engine.exemplar_demo_terrain(ELSEWHERE_SIZE, 4.0, 11).grid()
    hills = grid_terrain("Elsewhere", ELSEWHERE, grid["cell"], LIKE_RELIEF * np.asarray(grid["heights"]))
    scene.worldpaint.terrain = hills
    centre = (ELSEWHERE[0] + ELSEWHERE_SIZE / 2, ELSEWHERE[1] + ELSEWHERE_SIZE / 2)
    settings.region = square_curve("Elsewhere village", centre, LIKE_SIDE)
    run(bpy.ops.worldpaint.generate_village, seed=101)
    print(f"village: grown like {LIKE_VILLAGE} on other hills: {settings.report}")
    dress_place(scene, terrain)
    showcase.smooth(hills)
    showcase.backdrop("Land around the hills", *grid_of(hills), relief=0.3)
    showcase.cycles(scene, samples)
    showcase.sky(scene)
    showcase.sun(scene)
    size = (1152, 648)
    w, h = size[0] * percent // 100, size[1] * percent // 100
    seconds = 0.0
    for name, (cx, cy), ground_obj in (("demo_village_real", (x, y), terrain),
                                       ("demo_village_grown", centre, hills)):
        z = float(engine.terrain_from_grid(*grid_of(ground_obj)).heights_at(np.array([[cx, cy]]))[0])
        # from the south-east and high up, so the valley's sides do not hide the village
        cam = showcase.camera(f"Camera {name}", (cx + 350.0, cy - 520.0, z + 800.0), (cx, cy, z), 32.0)
        cam.data.clip_end = 40000.0
        seconds += showcase.render(scene, cam, out / f"{name}.png", (w, h))
    side_by_side(out / "demo_village_real.png", out / "demo_village_grown.png", out / "demo_village_like.png")
    return [("demo_village_like", seconds, (2 * size[0], size[1]))]


def world_prototypes():
    """A collection per category of the painted world, each one low-poly mesh with its material."""
    parent = bpy.data.collections.new("World prototypes")
    bpy.context.scene.collection.children.link(parent)
    shapes = {  # (radius, height, segments, leaves rgb) of a cone on a trunk, or of a lump (no trunk)
        "Pine": (2.2, 11.0, 7, (0.018, 0.05, 0.02)), "Oak": (3.2, 9.0, 8, (0.035, 0.08, 0.02)),
        "Bush": (1.1, 1.2, 6, (0.06, 0.09, 0.03)), "Shrub": (1.4, 1.6, 6, (0.07, 0.08, 0.035)),
        "Fern": (0.8, 0.6, 6, (0.05, 0.11, 0.02)), "Grass": (0.5, 0.5, 5, (0.12, 0.15, 0.04)),
        "Rock": (1.2, 0.9, 5, (0.16, 0.15, 0.14)),
    }
    for name, (radius, height, segments, rgb) in shapes.items():
        bm = bmesh.new()
        tall = name in ("Pine", "Oak")
        if tall:
            bmesh.ops.create_cone(bm, cap_ends=True, segments=5, radius1=0.25, radius2=0.2, depth=height * 0.3,
                                  matrix=Matrix.Translation((0.0, 0.0, height * 0.15)))
        if name == "Oak":
            bmesh.ops.create_icosphere(bm, subdivisions=1, radius=radius,
                                       matrix=Matrix.Translation((0.0, 0.0, height * 0.65)))
        else:
            bmesh.ops.create_cone(bm, cap_ends=True, segments=segments, radius1=radius, radius2=0.0 if tall else
                                  radius * 0.3, depth=height * (0.8 if tall else 1.0),
                                  matrix=Matrix.Translation((0.0, 0.0, height * (0.55 if tall else 0.5))))
        mesh = bpy.data.meshes.new(name)
        bm.to_mesh(mesh)
        bm.free()
        material = bpy.data.materials.new(name)
        (showcase.plain(material, rgb, grain=0.3) if name == "Rock" else showcase.leaves(material, rgb))
        mesh.materials.append(material)
        collection = bpy.data.collections.new(name)
        parent.children.link(collection)
        collection.objects.link(bpy.data.objects.new(name, mesh))
    bpy.context.view_layer.layer_collection.children[parent.name].exclude = True


def world_picture(out, samples, percent=100):
    """The painted world (see the module documentation); returns the report lines."""
    sys.path.insert(0, str(ROOT / "blender_tests"))
    import bench_world_painted as painted
    from worldpaint_engine import world

    if not painted.SRTM.is_file():
        raise SystemExit(f"the world picture needs {painted.SRTM}")
    showcase.HAZE_DISTANCE = 30000.0  # a view across 10 km of mountains, not across one valley
    side = 10000.0
    colors = [painted.learned(name, cats, 10 * k + 1) for k, (name, cats) in enumerate(painted.COLORS)]
    ground = painted.andorra(side)
    paint_map = painted.painted_map(ground, side, colors)
    sites = painted.village_sites(ground, side)
    folder = out / "demo_world"
    # a cluster of threads: worker processes would start this script again, and Blender with it
    from distributed import Client

    client = Client(processes=False, n_workers=1, threads_per_worker=2, dashboard_address=":0")
    try:
        start = time.perf_counter()
        manifest = world.fill_world(client, paint_map, folder, seed=1, region=((0.0, 0.0), (side, side)),
                                    terrain=ground, sites=sites, overwrite=True)
        filled = time.perf_counter() - start
    finally:
        client.close()
    print(f"world: {manifest['instances']:,} instances and {manifest['villages']['buildings']} buildings in "
          f"{filled:.1f} s")
    scene = bpy.context.scene
    terrain = grid_terrain("Andorra", ground.origin, ground.cell, ground.heights)
    world_prototypes()
    inside = sites[1]["position"]
    # from the road below the village, looking past it to the wooded slope above
    at, seen = (inside[0] + 60.0, inside[1] - 330.0), (inside[0] - 120.0, inside[1] + 250.0)
    z_at, z_seen = engine.terrain_from_grid(*grid_of(terrain)).heights_at(np.array([at, seen]))
    eye = showcase.camera("Camera world inside", (*at, float(z_at) + 30.0), (*seen, float(z_seen) + 20.0), 28.0)
    eye.data.clip_end = 20000.0
    scene.camera = eye
    run(bpy.ops.worldpaint.load_world, directory=str(folder), display='PROXY', lod_distance=1500.0)
    showcase.smooth(terrain)
    showcase.backdrop("Land around Andorra", *grid_of(terrain), relief=0.3)
    showcase.dress_materials()
    terrain.data.materials.clear()
    material = bpy.data.materials.new("Andorra ground")
    showcase.terrain(material)
    terrain.data.materials.append(material)
    showcase.cycles(scene, samples)
    showcase.sky(scene)
    showcase.sun(scene)
    size = (1152, 648)
    w, h = size[0] * percent // 100, size[1] * percent // 100
    above = showcase.camera("Camera world", (side * 0.5, -side * 0.05, 6000.0), (side * 0.5, side * 0.6, 1400.0), 40.0)
    above.data.clip_end = 40000.0
    report = []
    for name, cam in (("demo_world", above), ("demo_world_inside", eye)):
        seconds = showcase.render(scene, cam, out / f"{name}.png", (w, h))
        report.append((name, seconds, size))
    return report


def square_curve(name, centre, side):
    """A closed square curve of ``side`` metres around ``centre`` (a village's region)."""
    h = side / 2
    return poly_curve(name, [(centre[0] + dx, centre[1] + dy) for dx, dy in ((-h, -h), (h, -h), (h, h), (-h, h))],
                      cyclic=True)


def grid_of(terrain):
    """(origin, cell, heights (ny, nx)) of a grid terrain mesh."""
    co = np.empty(len(terrain.data.vertices) * 3)
    terrain.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    xs, ys = np.unique(co[:, 0]), np.unique(co[:, 1])
    return (float(xs[0]), float(ys[0])), float(xs[1] - xs[0]), co[:, 2].reshape(len(ys), len(xs))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="out", help="output folder")
    parser.add_argument("--samples", type=int, default=16, help="Cycles samples per pixel (denoised)")
    parser.add_argument("--percent", type=int, default=100, help="resolution of the pictures, in percent")
    parser.add_argument("--only", choices=["variants", "place", "village", "world"],
                        help="make and render only this picture")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    out = pathlib.Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)

    worldpaint.register()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    start = time.perf_counter()
    if args.only == "variants":
        birches = vary_birches()
        meadow = bpy.data.materials.new("Terrain")
        showcase.dress_materials()
        showcase.cycles(bpy.context.scene, args.samples)
        name, seconds, (w, h) = render_variants(out, birches, meadow, args.percent)
        print(f"  {name}.png  {w * args.percent // 100} x {h * args.percent // 100}  {seconds:5.1f} s")
        return
    if args.only in ("place", "village", "world"):
        picture = {"place": place_picture, "village": village_like_picture, "world": world_picture}[args.only]
        report = picture(out, args.samples, args.percent)
        bpy.ops.wm.save_as_mainfile(filepath=str(out / f"demo_{args.only}.blend"))
        for name, seconds, (w, h) in report:
            print(f"  {name}.png  {w * args.percent // 100} x {h * args.percent // 100}  {seconds:5.1f} s")
        return
    hills = build_and_learn()
    variants = vary_trees()
    birches = vary_birches()
    paint(hills)
    grow_hamlet(hills)
    fall = build_waterfall(hills)
    plant_vineyard(hills)
    painted = time.perf_counter() - start
    for obj in (o for o in bpy.data.collections["WorldPaint"].all_objects if not o.get("wp_village")):
        count = len(obj.data.splines) if obj.type == 'CURVE' else len(obj.data.vertices)
        print(f"{obj.name}: {count} {'curves' if obj.type == 'CURVE' else 'instances'}")
    dress(hills)
    denoised = showcase.cycles(bpy.context.scene, args.samples)
    report = render_all(out, fall, birches, args.percent)
    report += sketch_pictures(out, args.samples, variants, args.percent)
    bpy.context.scene.camera = bpy.data.objects["Camera demo"]
    bpy.ops.wm.save_as_mainfile(filepath=str(out / "demo.blend"))
    samples = bpy.context.scene.cycles.samples
    print(f"learned, painted and grew the hamlet in {painted:.1f} s; rendered with Cycles on the CPU, {samples} samples"
          f"{', denoised by OpenImageDenoise' if denoised else ' (no denoiser in this Blender)'}:")
    for name, seconds, (w, h) in report:
        print(f"  {name}.png  {w * args.percent // 100} x {h * args.percent // 100}  {seconds:5.1f} s")
    print(f"wrote {out / 'demo.blend'} and the pictures in {out} in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
