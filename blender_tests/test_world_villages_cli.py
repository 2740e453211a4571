"""Villages in a world on the command line: three sites on hills grow their villages before the tiles, joined by
roads; the tiles keep off the roads and the houses; one and two workers write the same bytes (villages included);
and every bad site is refused with one line before anything grows."""

import json

import numpy as np
import pytest
import worldpaint_engine as engine
from test_world_cli import assert_refused, cli, snapshot
from test_world_map_cli import meadow_color
from worldpaint_engine import world

pytest.importorskip("distributed", reason="filling worlds needs dask[distributed]")

SIDE = 1600.0
SITES = [{"x": 300, "y": 300, "type": "farming", "buildings": 12, "seed": 1},
         {"x": 1300, "y": 350, "type": "highland", "buildings": 12, "seed": 2},
         {"x": 800, "y": 1300, "type": "farming", "buildings": 12, "seed": 3}]


def write_hills(path):
    """Rolling hills over 1.6 km on 8 m samples, as an .asc (rows from the north)."""
    n = int(SIDE / 8.0) + 1
    x = np.arange(n) * 8.0
    h = 30.0 * np.sin(x[None, :] / 260.0) * np.cos(x[:, None] / 310.0) + 0.02 * x[None, :]
    rows = "\n".join(" ".join(f"{v:.3f}" for v in row) for row in h[::-1])
    path.write_text(f"ncols {n}\nnrows {n}\nxllcenter 0\nyllcenter 0\ncellsize 8\n" + rows + "\n")
    return path


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("village_inputs")
    palette = folder / "palette.json"
    palette.write_text(engine.palette_to_json([meadow_color()]))
    sites = folder / "sites.json"
    sites.write_text(json.dumps(SITES))
    return {"palette": palette, "terrain": write_hills(folder / "hills.asc"), "sites": sites}



def distance_to_polyline(xy, line):
    """Distance of every point of ``xy`` (N, 2) to the polyline ``line`` (M, 2)."""
    a, b = line[:-1], line[1:]
    ab = b - a
    t = np.clip(((xy[:, None, :] - a[None]) * ab[None]).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-12), 0.0, 1.0)
    nearest = a[None] + t[..., None] * ab[None]
    return np.linalg.norm(xy[:, None, :] - nearest, axis=-1).min(axis=1)


def inside_quad(xy, quad):
    """Whether each point of ``xy`` lies inside the convex quadrilateral ``quad`` (4, 2), either orientation."""
    signs = []
    for k in range(4):
        a, b = quad[k], quad[(k + 1) % 4]
        signs.append((b[0] - a[0]) * (xy[:, 1] - a[1]) - (b[1] - a[1]) * (xy[:, 0] - a[0]))
    signs = np.array(signs)
    return (signs > 0).all(axis=0) | (signs < 0).all(axis=0)


def test_villages_grow_before_the_tiles_which_keep_off_their_roads_and_houses(inputs, tmp_path):
    runs = {}
    for workers in (1, 2):
        out = tmp_path / f"world{workers}"
        run = cli("--palette", inputs["palette"], "--terrain", inputs["terrain"], "--villages", inputs["sites"],
                  "--tile", 400, "--seed", 2, "--out", out, "--workers", workers, "--quiet")
        assert run.returncode == 0, run.stderr
        assert "3 villages of" in run.stdout and "km of road" in run.stdout, run.stdout
        runs[workers] = snapshot(out)
    print(run.stdout)
    assert runs[1] == runs[2], "one and two workers grew or filled different worlds"
    out = tmp_path / "world2"
    manifest = world.read_manifest(out)
    assert manifest["villages"]["file"] == "villages.json" and manifest["villages"]["count"] == 3
    villages = json.loads((out / "villages.json").read_text())
    built = [len(v["footprints"]) for v in villages["villages"]]
    assert all(b >= 9 for b in built), built
    roads = [np.array(r)[:, :2] for r in villages["roads"]]
    roads += [np.array(r)[:, :2] for v in villages["villages"] for r in v["roads"]]
    quads = [np.array(f) for v in villages["villages"] for f in v["footprints"]]
    xy = np.concatenate([engine.read_world_tile((out / t["file"]).read_bytes())["positions"]
                         for t in manifest["tiles"]])
    half = villages["road_width"] / 2.0
    on_road = sum(int((distance_to_polyline(xy, r) < half).sum()) for r in roads if len(r) >= 2)
    in_house = sum(int(inside_quad(xy, q).sum()) for q in quads)
    print(f"{len(xy)} instances, {on_road} on a road, {in_house} in a house; buildings {built}")
    assert (on_road, in_house) == (0, 0)
    # each site stands on the roads between villages: every village is reachable from the others
    for s in SITES:
        at = np.array([[s["x"], s["y"]]], float)
        near = min(distance_to_polyline(at, r)[0] for r in roads[:len(villages["roads"])])
        assert near < 10.0, f"site {s} is {near:.1f} m off the roads between villages"


# (case, sites (a list, or the file's text), words the one line holds)
BAD_SITES = [
    ("site off the terrain", [dict(SITES[0], x=2500)], ["village site 1 at x 2500.0, y 300.0", "off the world"]),
    ("unknown type", [dict(SITES[0], type="metropolis")], ["village site 1", "'metropolis'", "farming"]),
    ("sites too near", [SITES[0], dict(SITES[1], x=400, y=400)], ["village site 2", "from village site 1", "apart"]),
    ("no buildings", [dict(SITES[0], buildings=0)], ["sites.json", "village site 1", "buildings 0", "from 1 to"]),
    ("fractional buildings", [dict(SITES[0], buildings=2.5)], ["sites.json", "buildings 2.5"]),
    ("nan x", "[{\"x\": NaN, \"y\": 3, \"type\": \"farming\", \"buildings\": 5}]", ["sites.json", "x nan", "finite"]),
    ("text y", [dict(SITES[0], y="north")], ["sites.json", "y 'north'", "finite number"]),
    ("missing type", [{"x": 300, "y": 300, "buildings": 5}], ["sites.json", "needs a village type"]),
    ("unknown key", [dict(SITES[0], people=40)], ["sites.json", "unknown key 'people'"]),
    ("negative seed", [dict(SITES[0], seed=-1)], ["sites.json", "seed -1"]),
    ("not JSON", "[{x: 1}", ["sites.json", "not JSON"]),
    ("empty list", [], ["sites.json", "at least one"]),
]


@pytest.mark.parametrize("case, sites, words", BAD_SITES, ids=[c[0] for c in BAD_SITES])
def test_a_bad_site_is_refused_with_one_line_before_anything_grows(inputs, tmp_path, case, sites, words):
    path = tmp_path / "sites.json"
    path.write_text(sites if isinstance(sites, str) else json.dumps(sites))
    out = tmp_path / "world"
    run = cli("--palette", inputs["palette"], "--terrain", inputs["terrain"], "--villages", path, "--out", out,
              "--quiet", timeout=60)
    print(f"{case}: {run.stderr.strip()}")
    assert_refused(run, words)
    assert not out.exists()


def test_villages_need_a_terrain_and_an_encyclopedia_needs_villages(inputs, tmp_path):
    run = cli("--palette", inputs["palette"], "--region", 0, 0, 400, 400, "--villages", inputs["sites"], "--out",
              tmp_path / "a", "--quiet", timeout=60)
    assert run.returncode == 2 and "villages grow on a --terrain" in run.stderr, run.stderr
    run = cli("--palette", inputs["palette"], "--terrain", inputs["terrain"], "--encyclopedia", inputs["sites"],
              "--out", tmp_path / "b", "--quiet", timeout=60)
    assert run.returncode == 2 and "--encyclopedia describes --villages" in run.stderr, run.stderr


def test_load_world_brings_in_the_villages_houses_and_roads_once(inputs, tmp_path):
    import bpy

    out = tmp_path / "world"
    run = cli("--palette", inputs["palette"], "--terrain", inputs["terrain"], "--villages", inputs["sites"], "--tile",
              800, "--seed", 2, "--out", out, "--workers", 1, "--quiet", timeout=600)
    assert run.returncode == 0, run.stderr
    villages = json.loads((out / "villages.json").read_text())
    houses = sum(len(v["houses"]) for v in villages["villages"])
    bpy.ops.worldpaint.load_world(directory=str(out), radius=500.0)
    made = [o for o in bpy.data.objects if o.get("wp_world_villages")]
    roads = [o for o in made if o.type == 'CURVE']
    built = [o for o in made if o.type == 'MESH']
    assert len(roads) == 1 and len(built) == houses >= 27, (len(roads), len(built), houses)
    assert len(roads[0].data.splines) == len(villages["roads"]) + sum(len(v["roads"]) for v in villages["villages"])
    # each house stands on its footprint
    centres = np.array([np.asarray(f)[:, :2].mean(axis=0) for v in villages["villages"] for f in v["footprints"]])
    for obj in built:
        assert np.hypot(*(centres - np.asarray(obj.location[:2])).T).min() < 0.01, obj.name
    # loading the rest of the tiles does not bring the villages in twice
    bpy.ops.worldpaint.load_world(directory=str(out))
    assert len([o for o in bpy.data.objects if o.get("wp_world_villages")]) == len(made)
