"""The WorldPaint sidebar tab of the 3D viewport; it only draws."""

import bpy

from .lists import WORLDPAINT_UL_categories, WORLDPAINT_UL_palette
from .panel import WORLDPAINT_PT_main

_classes = (WORLDPAINT_UL_categories, WORLDPAINT_UL_palette, WORLDPAINT_PT_main)

register, unregister = bpy.utils.register_classes_factory(_classes)
