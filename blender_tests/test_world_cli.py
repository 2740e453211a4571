"""The world command line's bad input, as a table: each case answers within 10 s with one line on stderr naming what
was given and the rule, exits non-zero, and creates nothing (an existing tile set stays byte for byte as it was);
the cases that are fine finish with exactly the tile set their manifest lists."""

import os
import signal
import socket
import subprocess
import sys
import time

import numpy as np
import pytest
import worldpaint_engine as engine
from bench_world import bench_color
from worldpaint_engine import world

pytest.importorskip("distributed", reason="filling worlds needs dask[distributed]")

PROG = "python -m worldpaint_engine.world"
ANSWER_WITHIN = 10.0

HILLS_HEADER = "ncols 41\nnrows 41\nxllcenter 0\nyllcenter 0\ncellsize 5\nNODATA_value -9999\n"


def hills():
    """Rolling hills over 200 m on 5 m samples, rows along +Y, to the millimetre (as an .asc holds them)."""
    x = np.linspace(0.0, 200.0, 41)
    h = 30.0 * np.sin(x[None, :] / 90.0) * np.cos(x[:, None] / 70.0)
    return np.array([[float(f"{v:.3f}") for v in row] for row in h])


def write_asc(path, header=HILLS_HEADER, heights=None):
    h = hills() if heights is None else heights
    rows = "\n".join(" ".join(f"{v:.3f}" for v in row) for row in h[::-1])
    path.write_text(header + rows + "\n")
    return path


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    """The palette (the benchmark color: 0.1 instances per m², a region of influence of about 18 m), an .asc and
    a .npy of the same hills, a plain file, and a tile set made once to be refused or replaced."""
    folder = tmp_path_factory.mktemp("inputs")
    palette = folder / "bench.json"
    palette.write_text(engine.palette_to_json([bench_color()]))
    asc = write_asc(folder / "hills.asc")
    npy = folder / "hills.npy"
    np.save(npy, hills())
    plain = folder / "notes.txt"
    plain.write_text("not a folder\n")
    old = folder / "old_world"
    run = cli("--palette", palette, "--region", 0, 0, 200, 200, "--tile", 50, "--out", old, "--workers", 1, "--quiet")
    assert run.returncode == 0, run.stderr
    return {"palette": palette, "asc": asc, "npy": npy, "plain": plain, "old": old, "folder": folder}


def cli(*args, timeout=120):
    return subprocess.run([sys.executable, "-m", "worldpaint_engine.world", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout)


def assert_refused(run, words):
    """``run`` exited 2 with one line on stderr, the command's error, holding each of ``words``."""
    assert run.returncode == 2, (run.returncode, run.stderr)
    lines = run.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"{PROG}: error: "), run.stderr
    for w in words:
        assert w in lines[0], f"'{w}' is not in: {lines[0]}"


def snapshot(folder):
    """Every file under ``folder``: {relative path: bytes}."""
    found = {}
    for root, _dirs, files in os.walk(folder):
        for name in files:
            path = os.path.join(root, name)
            found[os.path.relpath(path, folder)] = open(path, "rb").read()
    return found


def silent_server():
    """A TCP server on this machine that accepts connections and never answers (as a hung scheduler would)."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()
    return server


def closed_port():
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()  # nothing listens there now
    return port


def terrain_file(kind):
    """Writes a damaged terrain file into ``folder``: (file name, how to write it)."""
    def asc(header=HILLS_HEADER, heights=None):
        return lambda path: write_asc(path, header, heights)

    with_nan = hills()
    with_nan[7, 3] = np.nan
    with_inf = hills()
    with_inf[0, 0] = np.inf
    return {
        "cellsize 0": ("zero.asc", asc(HILLS_HEADER.replace("cellsize 5", "cellsize 0"))),
        "negative cellsize": ("negative.asc", asc(HILLS_HEADER.replace("cellsize 5", "cellsize -5"))),
        "nan cellsize": ("nancell.asc", asc(HILLS_HEADER.replace("cellsize 5", "cellsize nan"))),
        "missing ncols": ("nocols.asc", asc(HILLS_HEADER.replace("ncols 41\n", ""))),
        "missing yll": ("noyll.asc", asc(HILLS_HEADER.replace("yllcenter 0\n", ""))),
        "nan height": ("nan.asc", asc(heights=with_nan)),
        "all no-data": ("nodata.asc", asc(heights=np.full((41, 41), -9999.0))),
        "nan no-data": ("nanodata.asc", asc(HILLS_HEADER.replace("-9999", "nan"))),
        "short rows": ("short.asc", asc(HILLS_HEADER.replace("ncols 41", "ncols 42"))),
        "npy nan": ("nan.npy", lambda path: np.save(path, with_nan)),
        "npy inf": ("inf.npy", lambda path: np.save(path, with_inf)),
        "npy 1-D": ("line.npy", lambda path: np.save(path, hills()[0])),
        "npy 3-D": ("cube.npy", lambda path: np.save(path, np.zeros((4, 4, 4)))),
        "npy text": ("words.npy", lambda path: np.save(path, np.array([["a", "b"], ["c", "d"]]))),
        "npy damaged": ("damaged.npy", lambda path: path.write_bytes(b"\x93NUMPY\x01\x00garbage")),
    }[kind]


# (case, arguments after --palette (terrain files by kind, {out} for the output path), words the message holds)
REFUSED = [
    ("workers -3", ["--region", 0, 0, 200, 200, "--workers", -3], ["--workers", "-3", "from 1"]),
    ("workers 0", ["--region", 0, 0, 200, 200, "--workers", 0], ["--workers", "0", "from 1"]),
    ("tile 0", ["--region", 0, 0, 200, 200, "--tile", 0], ["--tile", "0", "greater than 0"]),
    ("tile -50", ["--region", 0, 0, 200, 200, "--tile", -50], ["--tile", "-50", "greater than 0"]),
    ("tile nan", ["--region", 0, 0, 200, 200, "--tile", "nan"], ["--tile", "nan", "finite"]),
    ("tile inf", ["--region", 0, 0, 200, 200, "--tile", "inf"], ["--tile", "inf", "finite"]),
    ("tile text", ["--region", 0, 0, 200, 200, "--tile", "wide"], ["--tile", "'wide'", "not a number"]),
    ("tile under the influence", ["--region", 0, 0, 200, 200, "--tile", 5],
     ["tiles of 5 m", "at least the region of influence"]),
    ("inverted region", ["--region", 200, 0, 0, 200], ["--region 200 0 0 200", "X1 must be greater than X0"]),
    ("empty region", ["--region", 0, 0, 200, 0], ["--region 0 0 200 0", "Y1 greater than Y0"]),
    ("nan region", ["--region", 0, "nan", 200, 200], ["--region", "nan", "finite"]),
    ("region of 10,000 km", ["--region", 0, 0, 1e7, 1e7], ["1e+07", "too large", "tiles", "1000000"]),
    ("a tile past the budget", ["--region", 0, 0, 1e5, 1e5, "--tile", 1e5],
     ["tiles of 100000 m", "too large", "instances", "50000000"]),
    ("no region, no terrain", [], ["--region X0 Y0 X1 Y1", "--terrain"]),
    ("seed -1", ["--region", 0, 0, 200, 200, "--seed", -1], ["--seed", "-1", "from 0"]),
    ("seed 2^64", ["--region", 0, 0, 200, 200, "--seed", 2**64], ["--seed", str(2**64), "18446744073709551615"]),
    ("seed 1.5", ["--region", 0, 0, 200, 200, "--seed", 1.5], ["--seed", "'1.5'", "whole number"]),
    ("iterations -5", ["--region", 0, 0, 200, 200, "--iterations", -5], ["--iterations", "-5", "greater than 0"]),
    ("iterations 0", ["--region", 0, 0, 200, 200, "--iterations", 0], ["--iterations", "0", "greater than 0"]),
    ("iterations 1e300", ["--region", 0, 0, 200, 200, "--iterations", 1e300], ["--iterations", "limit of 10,000"]),
    ("unknown color", ["--region", 0, 0, 200, 200, "--color", "Orchard"], ["no color 'Orchard'", "Bench"]),
    ("missing terrain", ["--terrain", "{folder}/missing.asc"], ["--terrain", "missing.asc", "No such file"]),
    ("terrain of another kind", ["--terrain", "{plain}"], ["notes.txt", ".asc, .npy or .blend"]),
    ("cell for an .asc", ["--terrain", "{asc}", "--cell", 5], ["--cell", "does not apply", ".asc"]),
    ("npy without a cell", ["--terrain", "{npy}"], ["hills.npy", "--cell"]),
    ("cell 0", ["--terrain", "{npy}", "--cell", 0], ["--cell", "0", "greater than 0"]),
    ("origin without a terrain", ["--region", 0, 0, 200, 200, "--origin", 0, 0], ["--origin", "--terrain"]),
    ("region off the terrain", ["--terrain", "{asc}", "--region", 500, 500, 900, 900],
     ["--region 500 500 900 900", "entirely off the terrain", "0 0 200 200"]),
    ("region off the npy", ["--terrain", "{npy}", "--cell", 5, "--origin", 1000, 1000, "--region", 0, 0, 200, 200],
     ["entirely off the terrain", "1000 1000 1200 1200"]),
    ("out under a file", ["--region", 0, 0, 200, 200, "--out", "{plain}/world"], ["--out", "notes.txt", "is a file"]),
    ("out is a file", ["--region", 0, 0, 200, 200, "--out", "{plain}"], ["--out", "notes.txt", "is a file"]),
    ("out under /proc", ["--region", 0, 0, 200, 200, "--out", "/proc/worldpaint/world"],
     ["--out /proc/worldpaint/world", "cannot create"]),
    ("out exists", ["--region", 0, 0, 200, 200, "--tile", 100, "--out", "{old}"], ["--out", "exists", "--overwrite"]),
    ("overwrite a folder of other files", ["--region", 0, 0, 200, 200, "--out", "{folder}", "--overwrite"],
     ["--out", "no tile set", "--overwrite replaces only"]),
    ("unreachable scheduler", ["--region", 0, 0, 200, 200, "--scheduler", "tcp://127.0.0.1:{closed}"],
     ["--scheduler tcp://127.0.0.1:", "no Dask scheduler answered within 5 s"]),
    ("silent scheduler", ["--region", 0, 0, 200, 200, "--scheduler", "tcp://127.0.0.1:{silent}"],
     ["--scheduler tcp://127.0.0.1:", "no Dask scheduler answered within 5 s"]),
    ("scheduler of an unknown kind", ["--region", 0, 0, 200, 200, "--scheduler", "carrier-pigeon://loft"],
     ["--scheduler carrier-pigeon://loft", "unknown address scheme"]),
    ("two kinds of progress", ["--region", 0, 0, 200, 200, "--quiet", "--progress-lines"],
     ["--progress-lines", "not allowed with argument --quiet"]),
    ("workers and a scheduler", ["--region", 0, 0, 200, 200, "--workers", 1, "--scheduler", "tcp://127.0.0.1:1"],
     ["--scheduler", "not allowed with argument --workers"]),
] + [(f"terrain: {kind}", ["--terrain", f"{{damaged:{kind}}}"] + (["--cell", 5] if "npy" in kind else []), words)
     for kind, words in [
         ("cellsize 0", ["zero.asc", "cellsize 0", "positive length"]),
         ("negative cellsize", ["negative.asc", "cellsize -5", "positive length"]),
         ("nan cellsize", ["nancell.asc", "cellsize nan", "positive length"]),
         ("missing ncols", ["nocols.asc", "no ncols"]),
         ("missing yll", ["noyll.asc", "yllcorner and yllcenter"]),
         ("nan height", ["nan.asc", "1 of its heights", "nan", "column 3, row 33", "NODATA_value"]),
         ("all no-data", ["nodata.asc", "every sample is no-data"]),
         ("nan no-data", ["nanodata.asc", "NODATA_value nan", "finite"]),
         ("short rows", ["short.asc", "41 x 41 values where the header says 42 x 41"]),
         ("npy nan", ["nan.npy", "1 of its heights", "nan", "column 3, row 7"]),
         ("npy inf", ["inf.npy", "inf", "column 0, row 0"]),
         ("npy 1-D", ["line.npy", "2-D array", "(41,)"]),
         ("npy 3-D", ["cube.npy", "2-D array", "(4, 4, 4)"]),
         ("npy text", ["words.npy", "real numbers", "<U1"]),
         ("npy damaged", ["damaged.npy", "not a readable .npy"]),
     ]]


@pytest.mark.parametrize("case, arguments, words", REFUSED, ids=[c[0] for c in REFUSED])
def test_bad_input_is_answered_in_time_with_one_line_and_nothing_created(inputs, tmp_path, case, arguments, words):
    server = silent_server()
    named = {"folder": inputs["folder"], "plain": inputs["plain"], "asc": inputs["asc"], "npy": inputs["npy"],
             "old": inputs["old"], "closed": closed_port(), "silent": server.getsockname()[1]}
    args = []
    for a in arguments:
        a = str(a)
        if a.startswith("{damaged:"):
            name, write = terrain_file(a[len("{damaged:"):-1])
            write(tmp_path / name)
            a = str(tmp_path / name)
        args.append(a.format(**named))
    out = tmp_path / "world"
    if "--out" not in args:
        args += ["--out", out]
    before, old_before = snapshot(tmp_path), snapshot(inputs["folder"])
    t0 = time.perf_counter()
    run = cli("--palette", inputs["palette"], *args, "--quiet", timeout=60)
    seconds = time.perf_counter() - t0
    server.close()
    print(f"{case}: {seconds:.1f} s: {run.stderr.strip()}")
    assert seconds < ANSWER_WITHIN, f"{case} took {seconds:.1f} s"
    assert_refused(run, words)
    assert snapshot(tmp_path) == before and not out.exists(), "a refused run left files"
    assert snapshot(inputs["folder"]) == old_before, "a refused run changed the inputs or the old tile set"
    assert not [n for n in os.listdir(inputs["folder"]) if ".partial-" in n]


def listed(folder):
    """The file names a tile set's manifest lists, with the manifest."""
    manifest = world.read_manifest(folder)
    return sorted([world.MANIFEST] + [t["file"] for t in manifest["tiles"]]), manifest


def test_a_region_partly_off_the_terrain_fills_the_part_on_it(inputs, tmp_path):
    out = tmp_path / "world"
    run = cli("--palette", inputs["palette"], "--terrain", inputs["asc"], "--region", -100, 50, 120, 400,
              "--seed", 2, "--out", out, "--workers", 1, "--progress-lines")
    assert run.returncode == 0, run.stderr
    assert "filling 0 50 120 200 (the part of --region on the terrain)" in run.stdout
    names, manifest = listed(out)
    # a line as each tile ends, for a program (Blender's Fill World) to follow
    n = len(manifest["tiles"])
    assert [line for line in run.stdout.splitlines() if line.startswith("tile ")] == \
        [f"tile {k} of {n}" for k in range(1, n + 1)]
    assert sorted(os.listdir(out)) == names
    assert (manifest["min"], manifest["max"]) == ([0.0, 50.0], [120.0, 200.0])
    # every instance stands on the terrain, at the heightmap's height
    for t in manifest["tiles"]:
        tile = engine.read_world_tile((out / t["file"]).read_bytes())
        xy = tile["positions"]
        assert xy[:, 0].min() >= 0.0 and xy[:, 0].max() <= 120.0 and xy[:, 1].min() >= 50.0
        expected = 30.0 * np.sin(xy[:, 0] / 90.0) * np.cos(xy[:, 1] / 70.0)
        assert np.abs(tile["heights"] - expected).max() < 0.1
    assert abs(manifest["instances"] / (120.0 * 150.0) - 0.1) < 0.01


def test_npy_and_asc_terrains_with_no_data_fill_the_same_world(inputs, tmp_path):
    # a hole of no-data samples takes the grid's lowest height; the same heights as .npy give the same bytes
    heights = hills()
    heights[20:23, 20:23] = -9999.0
    asc = write_asc(tmp_path / "holes.asc", heights=heights)
    filled = np.where(heights == -9999.0, hills().min(), heights)
    npy = tmp_path / "holes.npy"
    np.save(npy, filled)
    runs = [cli("--palette", inputs["palette"], "--terrain", asc, "--seed", 4, "--out", tmp_path / "a", "--quiet",
                "--workers", 1),
            cli("--palette", inputs["palette"], "--terrain", npy, "--cell", 5, "--origin", 0, 0, "--seed", 4, "--out",
                tmp_path / "b", "--quiet", "--workers", 1)]
    assert all(r.returncode == 0 for r in runs), [r.stderr for r in runs]
    assert snapshot(tmp_path / "a") == snapshot(tmp_path / "b")


def test_overwrite_replaces_the_whole_tile_set(inputs, tmp_path):
    out = tmp_path / "world"
    first = cli("--palette", inputs["palette"], "--region", 0, 0, 200, 200, "--tile", 50, "--out", out, "--workers", 1,
                "--quiet")
    assert first.returncode == 0, first.stderr
    assert len(world.read_manifest(out)["tiles"]) == 16
    again = cli("--palette", inputs["palette"], "--region", 0, 0, 200, 200, "--tile", 100, "--out", out,
                "--workers", 1, "--quiet", "--overwrite")
    assert again.returncode == 0, again.stderr
    names, manifest = listed(out)
    assert len(manifest["tiles"]) == 4
    assert sorted(os.listdir(out)) == names, "tiles of the old set were left beside the new one"
    assert not [n for n in os.listdir(tmp_path) if n != "world"], "the old set or the staging folder was left"


def test_an_interrupted_or_terminated_run_leaves_the_old_tile_set_as_it_was(inputs, tmp_path):
    out = tmp_path / "world"
    made = cli("--palette", inputs["palette"], "--region", 0, 0, 200, 200, "--tile", 50, "--out", out, "--workers", 1,
               "--quiet")
    assert made.returncode == 0, made.stderr
    old = snapshot(out)
    for sig in (signal.SIGTERM, signal.SIGINT):
        # about 1.6 million instances in 4 tiles: seconds of work, stopped once the first tile is under way
        args = ["--palette", inputs["palette"], "--region", 0, 0, 4000, 4000, "--tile", 2000, "--out", out,
                "--overwrite", "--workers", 1, "--quiet"]
        # as a user's terminal starts it: a suite run from a background job would pass SIGINT on ignored
        previous = signal.signal(signal.SIGINT, signal.default_int_handler)
        try:
            run = subprocess.Popen([sys.executable, "-m", "worldpaint_engine.world", *map(str, args)],
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        finally:
            signal.signal(signal.SIGINT, previous)
        try:
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline:
                partial = [n for n in os.listdir(tmp_path) if ".partial-" in n]
                if partial and any(n.endswith(".wpt") or n.endswith(".part")
                                   for n in os.listdir(tmp_path / partial[0])):
                    break
                assert run.poll() is None, run.communicate()
                time.sleep(0.05)
            run.send_signal(sig)
            stdout, stderr = run.communicate(timeout=ANSWER_WITHIN)
        finally:
            if run.poll() is None:
                run.kill()
        assert run.returncode == 130, stderr
        assert stderr.strip().splitlines() == [f"{PROG}: interrupted; {out} was left as it was"], stderr
        assert snapshot(out) == old, "a stopped run changed the old tile set"
        assert sorted(os.listdir(tmp_path)) == ["world"], "a stopped run left its staging folder"


def test_a_terminate_signal_inside_the_import_machinery_is_answered_once_it_returns():
    # an exception raised in a module lock's weakref callback is printed and ignored, and the run would go on: the
    # handler sends the signal again and answers it outside the callback
    code = compile("def callback(log):\n    import signal\n    signal.raise_signal(signal.SIGTERM)\n"
                   "    log.append('callback returned')\n", "<frozen importlib._bootstrap>", "exec")
    frozen = {}
    exec(code, frozen)
    log = []
    previous = signal.signal(signal.SIGTERM, world.interrupt)
    try:
        frozen["callback"](log)
        log.append("after the callback")
        time.sleep(ANSWER_WITHIN)
        log.append("never answered")
    except KeyboardInterrupt:
        log.append("answered")
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert log == ["callback returned", "after the callback", "answered"]
