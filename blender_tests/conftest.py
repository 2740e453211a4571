"""The bpy test suite drives the real add-on inside Blender-as-a-module: no mocks.

The add-on is imported from ``addon/`` and registered once; every test starts from Blender's empty factory scene.
"""

import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "addon"))
sys.path.insert(0, str(ROOT / "assets"))

import bpy  # noqa: E402
import worldpaint  # noqa: E402

worldpaint.register()  # in module mode the add-on also unregisters itself at exit (bpy hangs otherwise)


@pytest.fixture(autouse=True)
def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield bpy.context.scene
