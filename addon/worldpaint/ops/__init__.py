"""Operators, one per concern; each takes its inputs as properties defaulting to the selection and the panel."""

import bpy

from .clear import WORLDPAINT_OT_clear_region
from .convert import WORLDPAINT_OT_convert_to_objects
from .learn import WORLDPAINT_OT_learn_color
from .manage import WORLDPAINT_OT_find_categories, WORLDPAINT_OT_remove_color
from .palette_io import WORLDPAINT_OT_export_palette, WORLDPAINT_OT_import_palette
from .paste import WORLDPAINT_OT_paste_color

_classes = (
    WORLDPAINT_OT_learn_color,
    WORLDPAINT_OT_paste_color,
    WORLDPAINT_OT_clear_region,
    WORLDPAINT_OT_convert_to_objects,
    WORLDPAINT_OT_export_palette,
    WORLDPAINT_OT_import_palette,
    WORLDPAINT_OT_find_categories,
    WORLDPAINT_OT_remove_color,
)

register, unregister = bpy.utils.register_classes_factory(_classes)
