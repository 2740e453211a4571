"""Worlds in tiles on Dask: the command line and a LocalCluster write the same bytes, whatever the worker count and
even when a worker dies mid-run; bad input gets a clear message."""

import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
import worldpaint_engine as engine
from bench_world import bench_color
from worldpaint_engine import world

distributed = pytest.importorskip("distributed", reason="filling worlds needs dask[distributed]")


@pytest.fixture(scope="module")
def palette(tmp_path_factory):
    """A palette file of the benchmark color: trees hard-core, rocks uniform, grass clustered, 0.1 per m²."""
    path = tmp_path_factory.mktemp("palette") / "bench.json"
    path.write_text(engine.palette_to_json([bench_color()]))
    return path


@pytest.fixture(scope="module")
def heightmap(tmp_path_factory):
    """Rolling hills over 800 m as an ESRI ASCII grid (5 m samples, rows north to south)."""
    x = np.linspace(0.0, 800.0, 161)
    h = 30.0 * np.sin(x[None, :] / 90.0) * np.cos(x[:, None] / 70.0)
    path = tmp_path_factory.mktemp("terrain") / "hills.asc"
    header = "ncols 161\nnrows 161\nxllcenter 0\nyllcenter 0\ncellsize 5\nNODATA_value -9999\n"
    np.savetxt(path, h[::-1], fmt="%.3f", header=header.strip(), comments="")
    return path


def tile_set(folder):
    """The files of a tile set: {name: bytes}."""
    return {name: (folder / name).read_bytes() for name in sorted(os.listdir(folder))}


def cli(*args):
    return subprocess.run([sys.executable, "-m", "worldpaint_engine.world", *map(str, args)],
                          capture_output=True, text=True, timeout=600)


def local_client(workers):
    cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       dashboard_address=":0")
    return distributed.Client(cluster)


def test_one_worker_and_a_two_worker_cluster_write_the_same_world(palette, heightmap, tmp_path):
    one = tmp_path / "one"
    run = cli("--palette", palette, "--terrain", heightmap, "--region", 0, 0, 600, 600, "--tile", 150,
              "--seed", 5, "--out", one, "--workers", 1, "--quiet")
    assert run.returncode == 0, run.stderr
    print(run.stdout)
    manifest = world.read_manifest(one)
    assert (manifest["columns"], manifest["rows"]) == (4, 4)
    # the color's density over the whole world: 0.1 per m²
    assert abs(manifest["instances"] / (600.0 * 600.0) - 0.1) < 0.005
    assert [c["name"] for c in manifest["categories"]] == ["Tree", "Rock", "Grass"]

    color = world.color_by_name(palette.read_text(), "Bench")
    terrain = world.load_terrain(heightmap)
    two = tmp_path / "two"
    with local_client(2) as client:
        world.fill_world(client, color, two, seed=5, region=((0, 0), (600, 600)), terrain=terrain, tile=150)
    assert tile_set(one) == tile_set(two), "a second worker changed the world"

    # the instances stand on the terrain: their heights are the heightmap's
    tile = engine.read_world_tile((one / "tile_1_2.wpt").read_bytes())
    xy = tile["positions"]
    assert len(xy) > 1000 and xy[:, 0].min() >= 150 and xy[:, 0].max() <= 300
    expected = 30.0 * np.sin(xy[:, 0] / 90.0) * np.cos(xy[:, 1] / 70.0)
    assert np.abs(tile["heights"] - expected).max() < 0.1


def test_a_worker_killed_mid_run_leaves_the_world_unchanged(palette, tmp_path):
    color = world.color_by_name(palette.read_text())
    region = ((0.0, 0.0), (1000.0, 1000.0))
    reference, survivor = tmp_path / "reference", tmp_path / "survivor"
    with local_client(1) as client:
        world.fill_world(client, color, reference, seed=9, region=region, tile=250, iterations=60.0)
    with local_client(2) as client:
        pids = client.run(os.getpid)
        victim = next(iter(pids.values()))
        killed_at = []

        def kill_once_a_tile_is_written():
            # the tiles are written into a hidden folder beside the output, renamed into place when all are done
            while not killed_at:
                for staging in tmp_path.glob(".survivor.partial-*"):
                    written = [n for n in os.listdir(staging) if n.endswith(".wpt")]
                    if written:
                        os.kill(victim, signal.SIGKILL)
                        killed_at.append(len(written))
                        break
                time.sleep(0.01)

        killer = threading.Thread(target=kill_once_a_tile_is_written, daemon=True)
        killer.start()
        manifest = world.fill_world(client, color, survivor, seed=9, region=region, tile=250, iterations=60.0)
        killer.join(timeout=5)
    print(f"killed a worker with {killed_at} of {len(manifest['tiles'])} tiles written")
    assert killed_at and killed_at[0] < len(manifest["tiles"]), "the worker was killed after the world was done"
    assert not any(n.endswith(".part") for n in os.listdir(survivor))
    assert sorted(os.listdir(tmp_path)) == ["reference", "survivor"], "the staging folder was left"
    assert tile_set(reference) == tile_set(survivor), "a dead worker changed the world"


def test_bad_input_is_refused_with_a_message(palette, heightmap, tmp_path):
    run = cli("--palette", palette, "--color", "Orchard", "--out", tmp_path / "x", "--workers", 1)
    assert run.returncode == 2 and "no color 'Orchard'" in run.stderr and "Bench" in run.stderr
    run = cli("--palette", palette, "--terrain", tmp_path / "missing.asc", "--out", tmp_path / "x")
    assert run.returncode == 2 and "missing.asc" in run.stderr
    color = world.color_by_name(palette.read_text())
    with pytest.raises(engine.InputError, match="region of influence"):
        engine.world_plan(color, (0, 0), (500, 500), tile=5.0)
    with pytest.raises(engine.FileFormatError):
        engine.read_world_tile(b"WPTILE01 and then nothing sensible")


def test_blender_loads_the_tiles_near_the_camera_first_and_the_rest_on_demand(palette, tmp_path):
    import bpy
    from scene_kit import prototypes
    from worldpaint.bridge.instances import WORLD_TILE_TAG

    out = tmp_path / "world"
    run = cli("--palette", palette, "--region", 0, 0, 800, 800, "--tile", 200, "--seed", 3, "--out", out,
              "--workers", 1, "--quiet")
    assert run.returncode == 0, run.stderr
    manifest = world.read_manifest(out)
    counts = {f"{t['column']},{t['row']}": t["count"] for t in manifest["tiles"]}
    prototypes()
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.location = (50.0, 50.0, 120.0)
    scene.camera = camera

    def loaded():
        """{tile: instances} of the tile clouds in the scene (each tile's clouds counted once)."""
        found = {}
        for obj in bpy.data.objects:
            if obj.get(WORLD_TILE_TAG):
                found[obj[WORLD_TILE_TAG]] = found.get(obj[WORLD_TILE_TAG], 0) + len(obj.data.vertices)
        return found

    # within 250 m of the camera: the tiles of the nearest 2 x 2 (the next ones start 350 m away)
    bpy.ops.worldpaint.load_world(directory=str(out), radius=250.0)
    near = loaded()
    assert set(near) == {"0,0", "1,0", "0,1", "1,1"}
    assert all(near[t] == counts[t] for t in near)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    tree = bpy.data.objects["WP_Tree 0,0"]
    shown = sum(1 for i in depsgraph.object_instances if i.is_instance and i.parent and i.parent.original == tree)
    assert shown == len(tree.data.vertices) > 100
    # the instances keep the engine's heights (flat ground here) and the prototypes are the scene's collections
    assert abs(min(v.co.z for v in tree.data.vertices)) < 1e-6

    bpy.ops.worldpaint.load_world(directory=str(out))
    assert loaded() == counts, "loading again did not add exactly the missing tiles"
    assert len([c for c in bpy.data.collections if c.get("wp_world")]) == 1

    saved = tmp_path / "world.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(saved))
    bpy.ops.wm.open_mainfile(filepath=str(saved))
    assert loaded() == counts

    with pytest.raises(RuntimeError, match="no manifest.json"):
        bpy.ops.worldpaint.load_world(directory=str(tmp_path))
