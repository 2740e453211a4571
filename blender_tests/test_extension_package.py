"""The packaged extension (``make extension``) installs into a clean Blender, with the engine wheel bundled inside it,
and paints: what a user gets from Install from Disk, on every Blender the suite runs on. Its wheel installs on every
Linux distribution Blender supports (glibc 2.28 and later)."""

import io
import json
import os
import pathlib
import re
import subprocess
import sys
import tomllib
import zipfile

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]

# runs in a fresh Blender whose user folders are a temporary directory, without the development add-on
INSTALL_AND_PAINT = """
import json, pathlib, sys
import bpy
sys.path.insert(0, sys.argv[2])
bpy.ops.wm.read_factory_settings(use_empty=True)
result = {"install": sorted(bpy.ops.extensions.package_install_files(
    filepath=sys.argv[1], repo="user_default", enable_on_install=True))}
site = pathlib.Path(bpy.utils.user_resource('EXTENSIONS')) / ".local"
result["bundled_engine"] = sorted(str(p.relative_to(site)) for p in site.rglob("worldpaint_engine/__init__.py"))
import addon_utils
result["modules"] = [m.__name__ for m in addon_utils.modules() if m.__name__.endswith("worldpaint")]
# the scene kit builds through the add-on's facade: the installed extension's
import importlib
for name in ("", ".bridge", ".bridge.engine"):
    sys.modules["worldpaint" + name] = importlib.import_module("bl_ext.user_default.worldpaint" + name)
from scene_kit import select_only, slope_exemplar
_, examples, _ = slope_exemplar()
select_only(examples)
result["learn"] = sorted(bpy.ops.worldpaint.learn_color(region_mode='RECT', rect_min=(0, 0), rect_max=(100, 100)))
select_only([])
result["paste"] = sorted(bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(0, 100), rect_max=(200, 200)))
result["points"] = sum(len(o.data.vertices) for o in bpy.data.collections["WorldPaint"].objects)
print("RESULT " + json.dumps(result))
"""


OLDEST_GLIBC = (2, 28)  # Blender's own Linux baseline


@pytest.fixture(scope="module")
def extension_zip():
    build = subprocess.run(["make", "extension"], cwd=ROOT, capture_output=True, text=True)
    assert build.returncode == 0, build.stdout[-2000:] + build.stderr[-2000:]
    zips = sorted((ROOT / "dist").glob("worldpaint-*-linux-x64.zip"))
    assert zips, "make extension wrote no zip"
    return zips[-1]


def test_the_bundled_wheel_needs_no_newer_glibc_than_blender_itself(extension_zip):
    with zipfile.ZipFile(extension_zip) as archive:
        manifest = tomllib.loads(archive.read("blender_manifest.toml").decode())
        wheels = [n for n in archive.namelist() if n.startswith("wheels/") and n.endswith(".whl")]
        assert [f"./{n}" for n in wheels] == manifest["wheels"]
        assert manifest["platforms"] == ["linux-x64"] and manifest["blender_version_min"] == "4.5.0"
        (wheel,) = wheels
        tag = re.search(r"-manylinux_(\d+)_(\d+)_x86_64\.whl$", wheel)
        assert tag and (int(tag[1]), int(tag[2])) <= OLDEST_GLIBC, f"{wheel} is tagged for a newer glibc"
        with zipfile.ZipFile(io.BytesIO(archive.read(wheel))) as inner:
            (library,) = [n for n in inner.namelist() if n.endswith(".so")]
            binary = inner.read(library)
    # the symbol versions the engine's library asks of the C library, whatever its tag says
    needed = {tuple(map(int, m)) for m in re.findall(rb"GLIBC_(\d+)\.(\d+)", binary)}
    assert needed and max(needed) <= OLDEST_GLIBC, f"the engine needs glibc {max(needed)}"


def test_the_extension_zip_installs_into_a_clean_blender_and_paints(tmp_path, extension_zip):
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    run = subprocess.run([sys.executable, "-c", INSTALL_AND_PAINT, str(extension_zip), str(ROOT / "assets")], env=env,
                         capture_output=True, text=True, timeout=600)
    lines = [line for line in run.stdout.splitlines() if line.startswith("RESULT ")]
    assert lines, run.stdout[-2000:] + run.stderr[-2000:]
    result = json.loads(lines[-1][len("RESULT "):])
    assert result["install"] == ["FINISHED"]
    assert result["bundled_engine"], "the engine wheel inside the zip was not installed"
    assert result["modules"] == ["bl_ext.user_default.worldpaint"]
    assert result["learn"] == ["FINISHED"] and result["paste"] == ["FINISHED"]
    assert result["points"] > 100
