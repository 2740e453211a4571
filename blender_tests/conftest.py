"""The bpy test suite drives the real add-on inside Blender-as-a-module: no mocks.

The add-on is imported from ``addon/`` and registered once; every test starts from Blender's empty factory scene.
"""

import atexit
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "addon"))
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))

import bpy  # noqa: E402
import worldpaint  # noqa: E402

worldpaint.register()


def _unregister():
    # Blender-as-a-module does not exit while Python classes are still registered
    try:
        worldpaint.unregister()
    except Exception:  # noqa: BLE001 - best effort at interpreter exit
        pass


atexit.register(_unregister)


@pytest.fixture(autouse=True)
def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield bpy.context.scene
