"""Mutated arguments and terrain files for the world command line, run as users run it (``python -m
worldpaint_engine.world`` in a subprocess): none may print a traceback, hang or leave a file behind.

Each case starts from a valid command (a region, an .asc, a .npy with its cell and origin, or an .asc with a region
partly off it, on a Dask scheduler started once here) and makes one to three edits: a number made extreme or not a
number, an argument removed, repeated, swapped or added, the output put under a file, on an existing tile set or
under /proc, and (in half the cases) the terrain file damaged: a header key or value changed, removed or repeated, a
height made NaN or huge, rows cut, bytes flipped, an array of another type or shape. Then:

* a refusal (exit 2) comes within 10 s as one line on stderr, and the case's folder is left exactly as it was;
* an accepted run says what it will make before it starts; one of more than ``WORK`` proposals is terminated
  there and must stop within 10 s leaving nothing (exit 130), the others must finish (exit 0) with exactly the
  tile set their manifest lists, every tile readable and on the terrain's heights.

The mutations are seeded: a failing case is reproduced by its seed, and kept in ``REGRESSIONS``.
``WORLD_CLI_MUTATIONS`` cases run (default 200, about 30 s on two cores);
``WORLD_CLI_MUTATIONS=2000 .venv/bin/python -m pytest -q -s blender_tests/test_world_cli_mutated.py`` runs more.
Mutated palette files are the engine's driver's concern (``rust/worldpaint-core/tests/mutated_files.rs``).
"""

import io
import os
import random
import re
import shutil
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
import worldpaint_engine as engine
from bench_world import bench_color
from worldpaint_engine import world

distributed = pytest.importorskip("distributed", reason="filling worlds needs dask[distributed]")

CASES = int(os.environ.get("WORLD_CLI_MUTATIONS", "200"))
# seeds of mutations that once failed, kept as regression cases
REGRESSIONS = []
ANSWER_WITHIN = 10.0
FINISH_WITHIN = 60.0
# accepted runs of more chain proposals than this are terminated once they have said what they will make
WORK = 2_000_000
PROG = "python -m worldpaint_engine.world"

EXTREMES = ["0", "-1", "-3", "1e-12", "1e-3", "0.5", "7", "1e3", "1e6", "1e7", "1e300", "-1e300", "nan", "-nan",
            "inf", "-inf", str(2**64), str(2**64 - 1), "abc", "", "1e", "0x10", "1_000", " 5", "-", "--", "½"]
ASC_HEADER = ["ncols 41", "nrows 41", "xllcenter 0", "yllcenter 0", "cellsize 5", "NODATA_value -9999"]


def hills():
    x = np.linspace(0.0, 200.0, 41)
    return 30.0 * np.sin(x[None, :] / 90.0) * np.cos(x[:, None] / 70.0)


def asc_lines():
    return ASC_HEADER + [" ".join(f"{v:.3f}" for v in row) for row in hills()[::-1]]


def is_number(token):
    try:
        float(token)
    except ValueError:
        return False
    return True


def mutate_asc(rng):
    """The lines of a damaged .asc, as bytes."""
    lines = asc_lines()
    for _ in range(rng.randint(1, 3)):
        k = rng.randrange(len(lines))
        choice = rng.randrange(9)
        if k < len(ASC_HEADER) or choice < 2:
            k = rng.randrange(len(ASC_HEADER)) if choice < 2 else k
            key = lines[k].split()[0] if lines[k].split() else "cellsize"
            edit = rng.randrange(6)
            if edit == 0:
                lines[k] = f"{key} {rng.choice(EXTREMES)}"
            elif edit == 1:
                del lines[k]
            elif edit == 2:
                lines.insert(k, lines[k])
            elif edit == 3:
                lines.insert(k, f"{rng.choice(['xllcorner', 'dx', 'cellsize', 'nodata_value'])} "
                                f"{rng.choice(EXTREMES)}")
            elif edit == 4:
                lines[k] = lines[k].replace("center", "corner")
            else:
                lines[k] = key
            continue
        values = lines[k].split()
        if choice < 5 and values:
            values[rng.randrange(len(values))] = rng.choice(EXTREMES)
            lines[k] = " ".join(values)
        elif choice == 5:
            del lines[k]
        elif choice == 6:
            lines.insert(k, lines[k])
        elif choice == 7 and values:
            del values[rng.randrange(len(values))]
            lines[k] = " ".join(values)
        else:
            lines[k] += " 1.0"
    data = ("\n".join(lines) + "\n").encode("utf-8")
    if rng.random() < 0.1:
        data = data[:rng.randrange(len(data))]
    if rng.random() < 0.05:
        k = rng.randrange(len(data))
        data = data[:k] + bytes([rng.randrange(256)]) + data[k + 1:]
    return data


def mutate_npy(rng):
    """A damaged .npy, as bytes."""
    h = hills()
    edit = rng.randrange(8)
    if edit == 0:
        h = h.astype(rng.choice(["float32", "int16", "uint8", "complex64", "bool", "<U3", "float16"]))
    elif edit == 1:
        h = rng.choice([h.ravel(), h.reshape(41, 41, 1), h[:1], h[:, :1], h[:0], h.T, h[:2, :2], np.float64(3.0)])
    elif edit in (2, 3):
        for _ in range(rng.randint(1, 5)):
            h[rng.randrange(41), rng.randrange(41)] = float(rng.choice(["nan", "inf", "-inf", "1e300", "-3e38",
                                                                       "1e38", "0"]))
    buffer = io.BytesIO()
    np.save(buffer, h, allow_pickle=False)
    data = buffer.getvalue()
    if edit == 4:
        data = data[:rng.randrange(len(data))]
    elif edit == 5:
        k = rng.randrange(min(len(data), 128))
        data = data[:k] + bytes([rng.randrange(256)]) + data[k + 1:]
    elif edit == 6:
        data += bytes(rng.randrange(256) for _ in range(rng.randint(1, 64)))
    return data


class Inputs:
    """The files every case reads (never written by a case) and the tile set a case may be pointed at."""

    def __init__(self, folder, scheduler):
        self.folder = folder
        self.palette = folder / "bench.json"
        self.palette.write_text(engine.palette_to_json([bench_color()]))
        self.asc = folder / "hills.asc"
        self.asc.write_text("\n".join(asc_lines()) + "\n")
        self.npy = folder / "hills.npy"
        np.save(self.npy, hills())
        self.scheduler = scheduler
        self.old = folder / "old_world"
        run = subprocess.run([sys.executable, "-m", "worldpaint_engine.world", "--palette", str(self.palette),
                              "--region", "0", "0", "200", "200", "--tile", "50", "--out", str(self.old),
                              "--scheduler", scheduler, "--quiet"], capture_output=True, text=True, timeout=120)
        assert run.returncode == 0, run.stderr

    def bases(self):
        common = ["--palette", str(self.palette), "--seed", "1", "--tile", "100", "--iterations", "40", "--out",
                  "world", "--scheduler", self.scheduler, "--quiet"]
        return [
            ["--region", "0", "0", "200", "200"] + common,
            ["--terrain", "hills.asc"] + common,
            ["--terrain", "hills.npy", "--cell", "5", "--origin", "0", "0"] + common,
            ["--terrain", "hills.asc", "--region", "-50", "20", "150", "260"] + common,
        ]


def mutate_arguments(args, rng, inputs):
    """One to three edits of the argument list."""
    args = list(args)
    for _ in range(rng.randint(1, 3)):
        edit = rng.randrange(10)
        numbers = [k for k, a in enumerate(args) if is_number(a)]
        if edit <= 1 and numbers:
            args[rng.choice(numbers)] = rng.choice(EXTREMES)
        elif edit == 2 and numbers:
            # a slip of a digit or a sign: often still a valid command, sometimes a large one
            k = rng.choice(numbers)
            args[k] = f"{float(args[k]) * rng.choice([10.0, 100.0, 0.1, -1.0, 2.0]):g}"
        elif edit == 3 and args:
            del args[rng.randrange(len(args))]
        elif edit == 4:
            options = [k for k, a in enumerate(args) if a.startswith("--")]
            k = rng.choice(options)
            end = next((j for j in range(k + 1, len(args)) if args[j].startswith("--")), len(args))
            part = args[k:end]
            if rng.random() < 0.5:
                del args[k:end]
            else:
                args += part
        elif edit == 5 and len(args) > 1:
            i, j = rng.randrange(len(args)), rng.randrange(len(args))
            args[i], args[j] = args[j], args[i]
        elif edit == 6:
            args += rng.choice([["--overwrite"], ["--workers", rng.choice(["1", "0", "-3", "99", "x"])],
                                ["--cell", rng.choice(EXTREMES)], ["--origin", rng.choice(EXTREMES), "0"],
                                ["--object", "Terrain"], ["--color", rng.choice(["Bench", "Orchard", ""])],
                                ["--region"] + [rng.choice(EXTREMES + ["0", "200"]) for _ in range(4)],
                                ["--tile", rng.choice(EXTREMES)], ["--seed", rng.choice(EXTREMES)],
                                ["--iterations", rng.choice(EXTREMES)], ["--unknown"], ["--terrain"]])
        elif edit == 7:
            args += ["--out", rng.choice([str(inputs.palette) + "/world", "old_world", "/proc/worldpaint/world",
                                          "", "a/b/c/world", str(inputs.folder)])]
            if rng.random() < 0.5:
                args.append("--overwrite")
        elif edit == 8:
            args += ["--terrain", rng.choice(["missing.asc", str(inputs.palette), ".", "hills.npy", "hills.asc",
                                              "terrain.blend"])]
        else:
            args[rng.randrange(len(args))] = rng.choice(EXTREMES)
    # the scheduler named is always this test's, or a port of this machine where none listens: the edits must not
    # send a connection (or a name lookup) anywhere else
    for k, a in enumerate(args[:-1]):
        if a == "--scheduler" and not args[k + 1].startswith("-") and args[k + 1] != inputs.scheduler:
            args[k + 1] = inputs.scheduler
    return args


def snapshot(folder):
    found = {}
    for root, dirs, files in os.walk(folder):
        for name in files + [d + "/" for d in dirs]:
            path = os.path.join(root, name)
            found[os.path.relpath(path, folder)] = b"" if name.endswith("/") else open(path, "rb").read()
    return found


def last_value(args, option):
    value = None
    for k, a in enumerate(args[:-1]):
        if a == option:
            value = args[k + 1]
    return value


def check_tile_set(out):
    """A finished tile set: exactly the files its manifest lists, each readable with the counts it lists."""
    manifest = world.read_manifest(out)
    names = sorted([world.MANIFEST] + [t["file"] for t in manifest["tiles"]])
    assert sorted(os.listdir(out)) == names, f"{out} holds {sorted(os.listdir(out))}, the manifest lists {names}"
    for t in manifest["tiles"]:
        tile = engine.read_world_tile(open(os.path.join(out, t["file"]), "rb").read())
        assert len(tile["positions"]) == t["count"] and np.isfinite(tile["heights"]).all()
    return manifest


def run_case(seed, inputs, root):
    """Runs one mutated case; returns its outcome ("refused", "finished", "stopped") and seconds, or raises."""
    rng = random.Random(seed)
    folder = root / f"case{seed}"
    folder.mkdir()
    base = rng.randrange(len(inputs.bases()))
    args = inputs.bases()[base]
    terrain = last_value(args, "--terrain")
    if terrain == "hills.asc":
        (folder / terrain).write_bytes(mutate_asc(rng) if rng.random() < 0.5 else inputs.asc.read_bytes())
    else:
        (folder / "hills.asc").write_bytes(inputs.asc.read_bytes())
    (folder / "hills.npy").write_bytes(mutate_npy(rng) if terrain == "hills.npy" and rng.random() < 0.5
                                       else inputs.npy.read_bytes())
    args = mutate_arguments(args, rng, inputs)
    if "old_world" in args:
        shutil.copytree(inputs.old, folder / "old_world")
    before = snapshot(folder)
    started = time.monotonic()
    process = subprocess.Popen([sys.executable, "-m", "worldpaint_engine.world", *args], cwd=folder,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    said = []

    def read_stdout():
        for line in process.stdout:
            said.append(line)

    reader = threading.Thread(target=read_stdout, daemon=True)
    reader.start()
    stopped = False
    what = f"seed {seed}: {PROG} {' '.join(repr(a) for a in args)}"
    try:
        while process.poll() is None:
            waited = time.monotonic() - started
            plan = next((re.search(r"about ([\d,]+) instances", s) for s in said if s.startswith("filling")), None)
            if plan is None and waited > ANSWER_WITHIN:
                raise AssertionError(f"{what}: no answer in {ANSWER_WITHIN:.0f} s (a hang)")
            try:
                iterations = float(last_value(args, "--iterations") or 40.0)
            except ValueError:
                iterations = 40.0
            if plan and not stopped and int(plan.group(1).replace(",", "")) * iterations > WORK:
                process.terminate()
                stopped, started = True, time.monotonic()
            if waited > (ANSWER_WITHIN if stopped else FINISH_WITHIN):
                raise AssertionError(f"{what}: still running after {waited:.0f} s"
                                     f"{' of being terminated' if stopped else ''}")
            try:
                process.wait(timeout=0.02)
            except subprocess.TimeoutExpired:
                pass
        stderr = process.stderr.read()
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    reader.join(timeout=5)
    seconds = time.monotonic() - started
    assert "Traceback" not in stderr, f"{what}: a traceback\n{stderr}"
    if process.returncode == 0:
        assert not stderr.strip(), f"{what}: exit 0 with {stderr!r}"
        out = folder / last_value(args, "--out")
        manifest = check_tile_set(out)
        assert manifest["instances"] > 0 or "--region" in args
        after = snapshot(folder)
        changed = {p.rstrip("/") for p in set(before) | set(after) if before.get(p) != after.get(p)}
        target = os.path.relpath(out, folder)
        # only the output folder, what is in it and the parents made for it
        assert all(p == target or p.startswith(target + os.sep) or target.startswith(p + os.sep) for p in changed), \
            f"{what}: changed {sorted(changed)}"
        return "finished", seconds
    lines = stderr.splitlines()
    assert len(lines) == 1, f"{what}: exit {process.returncode} with {len(lines)} lines on stderr\n{stderr}"
    assert snapshot(folder) == before, f"{what}: a refused or stopped run changed its folder"
    if stopped:
        assert process.returncode == 130 and "interrupted" in lines[0], f"{what}: {process.returncode} {stderr}"
        return "stopped", seconds
    assert process.returncode == 2 and lines[0].startswith(f"{PROG}: error: "), f"{what}: {process.returncode} {stderr}"
    assert seconds < ANSWER_WITHIN, f"{what}: refused after {seconds:.1f} s"
    return "refused", seconds


@pytest.fixture(scope="module")
def scheduler():
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0") as c:
        yield c.scheduler_address


def test_mutated_arguments_and_terrains_get_a_message_or_a_whole_world(scheduler, tmp_path):
    inputs = Inputs(tmp_path, scheduler)
    seeds = list(REGRESSIONS) + list(range(CASES))
    started = time.monotonic()
    outcomes, slowest_refusal = {"refused": 0, "finished": 0, "stopped": 0}, 0.0
    with ThreadPoolExecutor(max_workers=2) as pool:
        for outcome, seconds in pool.map(lambda s: run_case(s, inputs, tmp_path), seeds):
            outcomes[outcome] += 1
            if outcome == "refused":
                slowest_refusal = max(slowest_refusal, seconds)
    print(f"{len(seeds)} mutated cases: {outcomes['refused']} refused (slowest {slowest_refusal:.1f} s), "
          f"{outcomes['finished']} finished with a whole tile set, {outcomes['stopped']} large ones stopped and "
          f"cleaned up; all in {time.monotonic() - started:.0f} s")
    assert outcomes["refused"] > len(seeds) / 4 and outcomes["finished"] > 0
