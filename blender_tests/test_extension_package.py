"""The packaged extension (``make extension``) installs into a clean Blender, with the engine wheel bundled inside it,
and paints: what a user gets from Install from Disk."""

import json
import os
import pathlib
import subprocess
import sys

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
from scene_kit import select_only, slope_exemplar
_, examples, _ = slope_exemplar()
select_only(examples)
result["learn"] = sorted(bpy.ops.worldpaint.learn_color(region_mode='RECT', rect_min=(0, 0), rect_max=(100, 100)))
select_only([])
result["paste"] = sorted(bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(0, 100), rect_max=(200, 200)))
result["points"] = sum(len(o.data.vertices) for o in bpy.data.collections["WorldPaint"].objects)
print("RESULT " + json.dumps(result))
"""


def test_the_extension_zip_installs_into_a_clean_blender_and_paints(tmp_path):
    build = subprocess.run(["make", "extension"], cwd=ROOT, capture_output=True,
                           text=True)
    assert build.returncode == 0, build.stdout[-2000:] + build.stderr[-2000:]
    zips = sorted((ROOT / "dist").glob("worldpaint-*-linux-x64.zip"))
    assert zips, "make extension wrote no zip"

    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    run = subprocess.run([sys.executable, "-c", INSTALL_AND_PAINT, str(zips[-1]), str(ROOT / "assets")], env=env,
                         capture_output=True, text=True, timeout=600)
    lines = [line for line in run.stdout.splitlines() if line.startswith("RESULT ")]
    assert lines, run.stdout[-2000:] + run.stderr[-2000:]
    result = json.loads(lines[-1][len("RESULT "):])
    assert result["install"] == ["FINISHED"]
    assert result["bundled_engine"], "the engine wheel inside the zip was not installed"
    assert result["modules"] == ["bl_ext.user_default.worldpaint"]
    assert result["learn"] == ["FINISHED"] and result["paste"] == ["FINISHED"]
    assert result["points"] > 100
