"""The World panel in Blender: a map painted on the terrain with the palette's swatches, village sites placed as
empties, and Fill World running the world command line on a local Dask cluster and loading what it made; bad
input is answered in Blender's UI with the scene and the tile set as they were."""

import json

import bpy
import numpy as np
import pytest
import worldpaint_engine as engine
from bench_world import bench_color
from test_world_map_cli import meadow_color
from test_world_villages_cli import inside_quad

pytest.importorskip("distributed", reason="filling worlds needs dask[distributed]")

WIDTH, DEPTH, CELL = 600.0, 400.0, 10.0
BOUNDARY = 300.0  # painted: the benchmark color west of it, the meadow east


def hills(x, y):
    return 20.0 * np.sin(x / 130.0) * np.cos(y / 90.0)


@pytest.fixture
def scene(empty_scene):
    """A terrain of 600 x 400 m on 10 m cells with the palette [Bench, Meadow]."""
    nx, ny = int(WIDTH / CELL) + 1, int(DEPTH / CELL) + 1
    xs, ys = np.meshgrid(np.arange(nx) * CELL, np.arange(ny) * CELL)
    vertices = np.column_stack([xs.ravel(), ys.ravel(), hills(xs, ys).ravel()])
    faces = [(j * nx + i, j * nx + i + 1, (j + 1) * nx + i + 1, (j + 1) * nx + i)
             for j in range(ny - 1) for i in range(nx - 1)]
    mesh = bpy.data.meshes.new("Terrain")
    mesh.from_pydata(vertices.tolist(), [], faces)
    terrain = bpy.data.objects.new("Terrain", mesh)
    empty_scene.collection.objects.link(terrain)
    settings = empty_scene.worldpaint
    settings.terrain = terrain
    for color in (bench_color(), meadow_color()):
        entry = settings.palette.add()
        entry.name, entry.json = engine.color_summary(color)["name"], color
    return empty_scene


def paint_halves(terrain, swatches, noise=0.04, seed=1):
    """Paints the map as a brush would, not exactly: each vertex its half's swatch, a few per cent off."""
    attribute = terrain.data.color_attributes["WP World Map"]
    x = np.array([v.co.x for v in terrain.data.vertices])
    rgb = np.where((x < BOUNDARY)[:, None], swatches[0], swatches[1])
    rgb = np.clip(rgb + np.random.default_rng(seed).normal(0.0, noise, rgb.shape), 0.0, 1.0)
    attribute.data.foreach_set("color_srgb", np.column_stack([rgb, np.ones(len(rgb))]).ravel().astype(np.float32))


def loaded(category):
    """World XY of every loaded instance of ``category``."""
    xy = [np.array([v.co[:2] for v in obj.data.vertices]) for obj in bpy.data.objects
          if obj.get("wp_world_category") == category]
    return np.concatenate(xy) if xy else np.zeros((0, 2))


def test_a_painted_map_fills_each_part_with_its_color_and_loads_the_world(scene, tmp_path):
    settings = scene.worldpaint
    assert bpy.ops.worldpaint.paint_world_map() == {'FINISHED'}
    swatches = bpy.data.palettes["WorldPaint World Map"]
    assert len(swatches.colors) == 2
    terrain = settings.terrain
    # a new map is all the active color
    attribute = terrain.data.color_attributes["WP World Map"]
    assert np.allclose(attribute.data[0].color_srgb[:3], swatches.colors[0].color, atol=0.01)
    paint_halves(terrain, [np.array(c.color) for c in swatches.colors])

    settings.world.directory = str(tmp_path / "world")
    settings.world.seed = 3
    assert bpy.ops.worldpaint.fill_world() == {'FINISHED'}
    manifest = json.loads((tmp_path / "world" / "manifest.json").read_text())
    assert manifest["colors"] == ["Bench", "Meadow"]
    collections = [c for c in bpy.data.collections if c.get("wp_world")]
    assert len(collections) == 1
    clouds = [o for o in collections[0].objects if o.get("wp_world_category")]
    assert sum(len(o.data.vertices) for o in clouds) == manifest["instances"]
    assert "instances in" in settings.world.report

    # each color on its painted side, at its own density away from the band
    band = manifest["influence"] * 3.0
    trees, bushes = loaded("Tree"), loaded("Bush")
    assert trees[:, 0].max() < BOUNDARY + band / 2.0 + CELL and bushes[:, 0].min() > BOUNDARY - band / 2.0 - CELL
    west = (BOUNDARY - band / 2.0 - CELL) * DEPTH
    east = (WIDTH - BOUNDARY - band / 2.0 - CELL) * DEPTH
    bench = sum(len(loaded(c)) for c in ("Tree", "Rock", "Grass"))
    near_west = sum((loaded(c)[:, 0] < west / DEPTH).sum() for c in ("Tree", "Rock", "Grass"))
    print(f"bench {near_west / west:.4f} per m² west, meadow {(bushes[:, 0] > WIDTH - east / DEPTH).sum() / east:.4f}"
          f" east, {bench} bench instances")
    assert abs(near_west / west - 0.1) < 0.015
    assert abs((bushes[:, 0] > WIDTH - east / DEPTH).sum() / east - 0.01) < 0.003
    # the instances stand on the terrain
    tile = next(o for o in clouds if o.get("wp_world_category") == "Tree")
    co = np.array([v.co for v in tile.data.vertices])
    assert np.abs(co[:, 2] - hills(co[:, 0], co[:, 1])).max() < 0.5

    # filling again replaces the loaded world: one collection, the new tile set's instances
    settings.world.seed = 4
    assert bpy.ops.worldpaint.fill_world() == {'FINISHED'}
    manifest = json.loads((tmp_path / "world" / "manifest.json").read_text())
    collections = [c for c in bpy.data.collections if c.get("wp_world")]
    assert len(collections) == 1
    assert sum(len(o.data.vertices) for o in collections[0].objects if o.get("wp_world_category")) \
        == manifest["instances"]


def test_without_a_map_the_world_is_the_active_color(scene, tmp_path):
    scene.worldpaint.active_color_index = 1
    scene.worldpaint.world.directory = str(tmp_path / "world")
    assert bpy.ops.worldpaint.fill_world() == {'FINISHED'}
    manifest = json.loads((tmp_path / "world" / "manifest.json").read_text())
    assert manifest["colors"] == ["Meadow"]
    assert abs(manifest["instances"] / (WIDTH * DEPTH) - 0.01) < 0.002


def add_site(x, y, **kwargs):
    bpy.context.scene.cursor.location = (x, y, 0.0)
    assert bpy.ops.worldpaint.add_village_site(**kwargs) == {'FINISHED'}
    return bpy.context.view_layer.objects.active


def test_village_sites_grow_villages_the_world_keeps_off(scene, tmp_path):
    first = add_site(110.0, 200.0, buildings=6)
    second = add_site(490.0, 220.0, buildings=6)
    assert first.worldpaint_site.is_site and (first.worldpaint_site.seed, second.worldpaint_site.seed) == (0, 1)
    assert abs(first.location.z - 15.0 - hills(110.0, 200.0)) < 0.5  # above the ground
    scene.worldpaint.active_color_index = 0
    scene.worldpaint.world.directory = str(tmp_path / "world")
    assert bpy.ops.worldpaint.fill_world() == {'FINISHED'}
    villages = json.loads((tmp_path / "world" / "villages.json").read_text())
    houses = [o for o in bpy.data.objects if o.get("wp_world_villages") == "house"]
    built = sum(len(v["footprints"]) for v in villages["villages"])
    assert len(houses) == built >= 8, built
    assert f"{built} buildings in 2 villages" in scene.worldpaint.world.report
    xy = np.concatenate([loaded(c) for c in ("Tree", "Rock", "Grass")])
    for v in villages["villages"]:
        for footprint in v["footprints"]:
            assert not inside_quad(xy, np.asarray(footprint)[:4, :2]).any()


def world_left_as_it_was(tmp_path):
    return not (tmp_path / "world").exists() and not any(c.get("wp_world") for c in bpy.data.collections)


@pytest.mark.parametrize("case", ["off the terrain", "unknown type"])
def test_a_bad_site_is_answered_naming_its_empty(scene, tmp_path, case):
    site = add_site(300.0, 200.0, buildings=5)
    site.name = "Hilltop"
    if case == "off the terrain":
        site.location.x = 5000.0
    else:
        site.worldpaint_site.village_type = "farmnig"
    scene.worldpaint.world.directory = str(tmp_path / "world")
    with pytest.raises(RuntimeError) as error:
        bpy.ops.worldpaint.fill_world()
    print(error.value)
    assert "Hilltop" in str(error.value) and "--villages" not in str(error.value)
    assert ("off the world's terrain" if case == "off the terrain" else "farmnig") in str(error.value)
    assert world_left_as_it_was(tmp_path)


def test_fill_world_refuses_what_it_cannot_fill(scene, tmp_path):
    scene.worldpaint.world.directory = str(tmp_path / "world")
    (tmp_path / "world").mkdir()
    (tmp_path / "world" / "notes.txt").write_text("mine")
    with pytest.raises(RuntimeError, match="not a tile set|other files|refus"):
        bpy.ops.worldpaint.fill_world()
    assert (tmp_path / "world" / "notes.txt").read_text() == "mine"
    (tmp_path / "world" / "notes.txt").unlink()
    (tmp_path / "world").rmdir()

    scene.worldpaint.world.directory = "//world"  # the .blend is not saved
    with pytest.raises(RuntimeError, match="not saved"):
        bpy.ops.worldpaint.fill_world()
    scene.worldpaint.palette.clear()
    scene.worldpaint.world.directory = str(tmp_path / "world")
    with pytest.raises(RuntimeError, match="no colors"):
        bpy.ops.worldpaint.fill_world()
    with pytest.raises(RuntimeError, match="no colors"):
        bpy.ops.worldpaint.paint_world_map()
    scene.worldpaint.terrain = None
    with pytest.raises(RuntimeError, match="No terrain"):
        bpy.ops.worldpaint.fill_world()
    assert world_left_as_it_was(tmp_path)


def test_the_map_sites_and_settings_survive_save_and_reload_and_the_default_folder_is_beside_the_blend(
        scene, tmp_path):
    bpy.ops.worldpaint.paint_world_map()
    terrain = scene.worldpaint.terrain
    swatches = bpy.data.palettes["WorldPaint World Map"]
    paint_halves(terrain, [np.array(c.color) for c in swatches.colors], noise=0.0)
    add_site(300.0, 200.0, buildings=7).name = "Hilltop"
    world = scene.worldpaint.world
    world.band, world.seed, world.lod_distance, world.display = 80.0, 9, 250.0, 'BOUNDS'
    assert world.directory == "//world"
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "painted.blend"))
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "painted.blend"))

    scene = bpy.context.scene
    world = scene.worldpaint.world
    assert (world.band, world.seed, world.lod_distance, world.display) == (80.0, 9, 250.0, 'BOUNDS')
    site = bpy.data.objects["Hilltop"].worldpaint_site
    assert site.is_site and (site.village_type, site.buildings) == ("farming", 7)
    rgb = np.empty(len(scene.worldpaint.terrain.data.vertices) * 4, dtype=np.float32)
    scene.worldpaint.terrain.data.color_attributes["WP World Map"].data.foreach_get("color_srgb", rgb)
    assert len(np.unique(rgb.reshape(-1, 4)[:, :3].round(2), axis=0)) == 2
    assert bpy.ops.worldpaint.fill_world() == {'FINISHED'}
    manifest = json.loads((tmp_path / "world" / "manifest.json").read_text())
    assert manifest["colors"] == ["Bench", "Meadow"] and manifest["villages"]["count"] == 1


def test_a_map_painted_inside_drawn_curves(scene, tmp_path):
    settings = scene.worldpaint
    bpy.ops.curve.primitive_bezier_circle_add(radius=90.0, location=(150.0, 200.0, 0.0))
    clearing = bpy.context.view_layer.objects.active
    assert bpy.ops.worldpaint.paint_map_in_curves(color="Meadow") == {'FINISHED'}
    # the map is all Bench (the active color) but for the circle, painted with the meadow
    rgb = np.empty(len(settings.terrain.data.vertices) * 4, dtype=np.float32)
    settings.terrain.data.color_attributes["WP World Map"].data.foreach_get("color_srgb", rgb)
    xy = np.array([v.co[:2] for v in settings.terrain.data.vertices])
    meadow = np.abs(rgb.reshape(-1, 4)[:, :3] - bpy.data.palettes["WorldPaint World Map"].colors[1].color).max(1) < 0.01
    assert (meadow == (np.hypot(xy[:, 0] - 150.0, xy[:, 1] - 200.0) < 90.0)).mean() > 0.995

    settings.world.directory = str(tmp_path / "world")
    assert bpy.ops.worldpaint.fill_world() == {'FINISHED'}
    band = json.loads((tmp_path / "world" / "manifest.json").read_text())["influence"] * 3.0
    trees = loaded("Tree")
    assert len(trees) > 1000
    assert np.hypot(trees[:, 0] - 150.0, trees[:, 1] - 200.0).min() > 90.0 - band / 2.0 - CELL
    bushes = loaded("Bush")
    assert np.hypot(bushes[:, 0] - 150.0, bushes[:, 1] - 200.0).max() < 90.0 + band / 2.0 + CELL

    # what cannot be painted is said
    clearing.select_set(False)
    with pytest.raises(RuntimeError, match="Select the closed curves"):
        bpy.ops.worldpaint.paint_map_in_curves()
    clearing.select_set(True)
    with pytest.raises(RuntimeError, match="no color 'Orchard'"):
        bpy.ops.worldpaint.paint_map_in_curves(color="Orchard")
    clearing.data.splines[0].use_cyclic_u = False
    with pytest.raises(RuntimeError, match="not closed"):
        bpy.ops.worldpaint.paint_map_in_curves()


@pytest.mark.parametrize("float_buffer", [False, True], ids=["byte image", "float image"])
def test_a_map_painted_from_a_land_use_image(scene, float_buffer):
    settings = scene.worldpaint
    bpy.ops.worldpaint.paint_world_map()
    swatches = bpy.data.palettes["WorldPaint World Map"].colors
    # the land-use image's own colors, given to the swatches
    forest, meadow = (0.15, 0.45, 0.2), (0.85, 0.8, 0.35)
    swatches[0].color, swatches[1].color = forest, meadow
    image = bpy.data.images.new("Land use", 60, 40, float_buffer=float_buffer)
    srgb = np.where((np.arange(60) < 20)[None, :, None], forest, meadow) * np.ones((40, 1, 1))
    values = srgb if not float_buffer else np.where(srgb <= 0.04045, srgb / 12.92, ((srgb + 0.055) / 1.055) ** 2.4)
    image.pixels.foreach_set(np.concatenate([values, np.ones((40, 60, 1))], axis=2).ravel().astype(np.float32))
    assert bpy.ops.worldpaint.paint_map_from_image(image="Land use") == {'FINISHED'}

    rgb = np.empty(len(settings.terrain.data.vertices) * 4, dtype=np.float32)
    settings.terrain.data.color_attributes["WP World Map"].data.foreach_get("color_srgb", rgb)
    x = np.array([v.co.x for v in settings.terrain.data.vertices])
    is_forest = np.abs(rgb.reshape(-1, 4)[:, :3] - forest).max(axis=1) < 0.01
    # the image's first third (20 of 60 pixels) is the terrain's first 200 m
    assert (is_forest == (x < 200.0)).all()
    with pytest.raises(RuntimeError, match="No image 'Land usage'"):
        bpy.ops.worldpaint.paint_map_from_image(image="Land usage")


def test_a_site_is_not_added_off_the_terrain(scene):
    scene.cursor.location = (900.0, 200.0, 0.0)
    with pytest.raises(RuntimeError, match=r"3D cursor \(900.0, 200.0\) is not over the terrain"):
        bpy.ops.worldpaint.add_village_site()
    assert not any(o.worldpaint_site.is_site for o in bpy.data.objects)


def test_a_sites_type_is_picked_from_the_encyclopedia(scene):
    site = add_site(300.0, 200.0)
    assert bpy.ops.worldpaint.set_site_type(village_type="highland") == {'FINISHED'}
    assert site.worldpaint_site.village_type == "highland"
    with pytest.raises(RuntimeError, match="no village type 'hihgland'.*farming"):
        bpy.ops.worldpaint.set_site_type(village_type="hihgland")
    assert site.worldpaint_site.village_type == "highland"
    scene.worldpaint.terrain.select_set(True)
    bpy.context.view_layer.objects.active = scene.worldpaint.terrain
    with pytest.raises(RuntimeError, match="Select a village site"):
        bpy.ops.worldpaint.set_site_type(village_type="farming")
