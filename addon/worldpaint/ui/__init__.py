"""The WorldPaint sidebar tab and toolbar tools of the 3D viewport; they only draw."""

import bpy

from . import place, sketch, terrain_edit, tools, variety, village, world
from .lists import WORLDPAINT_UL_categories, WORLDPAINT_UL_interactions, WORLDPAINT_UL_palette
from .panel import (
    WORLDPAINT_PT_display,
    WORLDPAINT_PT_edit,
    WORLDPAINT_PT_interactions,
    WORLDPAINT_PT_learn_matrix,
    WORLDPAINT_PT_main,
    WORLDPAINT_PT_paint,
    WORLDPAINT_PT_palette,
)

_classes = (
    WORLDPAINT_UL_categories,
    WORLDPAINT_UL_palette,
    WORLDPAINT_UL_interactions,
    WORLDPAINT_PT_main,
    WORLDPAINT_PT_palette,
    WORLDPAINT_PT_interactions,
    WORLDPAINT_PT_paint,
    WORLDPAINT_PT_learn_matrix,
    WORLDPAINT_PT_edit,
    WORLDPAINT_PT_display,
    world.WORLDPAINT_MT_site_types,
    world.WORLDPAINT_PT_world,
    *village.classes,
    *place.classes,
    *terrain_edit.classes,
    *sketch.classes,
    *variety.classes,
)

_register_classes, _unregister_classes = bpy.utils.register_classes_factory(_classes)


def register():
    _register_classes()
    tools.register()
    place.register()


def unregister():
    place.unregister()
    tools.unregister()
    _unregister_classes()
