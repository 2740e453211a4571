"""Operators, one per concern; each takes its inputs as properties defaulting to the selection and the panel."""

import bpy

from ..bridge import snap
from . import (
    arrangement,
    display,
    drag,
    place,
    sketch_draw,
    variety,
    variety_texture,
    variety_tools,
    world,
    world_fill,
)
from .blur import WORLDPAINT_OT_blur
from .brush import WORLDPAINT_OT_brush, WORLDPAINT_OT_brush_radius, WORLDPAINT_OT_erase
from .builtin import WORLDPAINT_OT_add_builtin_color
from .clear import WORLDPAINT_OT_clear_region
from .colors import (
    WORLDPAINT_OT_duplicate_color,
    WORLDPAINT_OT_interpolate_colors,
    WORLDPAINT_OT_move_color,
    WORLDPAINT_OT_remove_color,
    WORLDPAINT_OT_toggle_interaction,
)
from .convert import WORLDPAINT_OT_convert_to_objects
from .gradient import WORLDPAINT_OT_gradient
from .learn import WORLDPAINT_OT_learn_color, WORLDPAINT_OT_set_learn_relation, WORLDPAINT_OT_toggle_learn_map
from .manage import WORLDPAINT_OT_find_categories
from .move import WORLDPAINT_OT_move_region
from .palette_io import WORLDPAINT_OT_export_palette, WORLDPAINT_OT_import_palette
from .paste import WORLDPAINT_OT_paste_color
from .pipette import WORLDPAINT_OT_pipette
from .sketch import WORLDPAINT_OT_apply_sketch
from .stretch import WORLDPAINT_OT_stretch_region
from .terrain_edit import WORLDPAINT_OT_build_waterfall, WORLDPAINT_OT_embed_roads
from .village import (
    WORLDPAINT_OT_add_village_event,
    WORLDPAINT_OT_export_encyclopedia,
    WORLDPAINT_OT_generate_village,
    WORLDPAINT_OT_learn_village,
    WORLDPAINT_OT_load_village_preset,
    WORLDPAINT_OT_move_village_event,
    WORLDPAINT_OT_remove_village_event,
    WORLDPAINT_OT_show_interest,
)

_classes = (
    WORLDPAINT_OT_learn_color,
    WORLDPAINT_OT_toggle_learn_map,
    WORLDPAINT_OT_set_learn_relation,
    WORLDPAINT_OT_paste_color,
    WORLDPAINT_OT_clear_region,
    WORLDPAINT_OT_convert_to_objects,
    WORLDPAINT_OT_export_palette,
    WORLDPAINT_OT_import_palette,
    WORLDPAINT_OT_add_builtin_color,
    WORLDPAINT_OT_find_categories,
    WORLDPAINT_OT_remove_color,
    WORLDPAINT_OT_duplicate_color,
    WORLDPAINT_OT_move_color,
    WORLDPAINT_OT_interpolate_colors,
    WORLDPAINT_OT_toggle_interaction,
    WORLDPAINT_OT_brush,
    WORLDPAINT_OT_erase,
    WORLDPAINT_OT_brush_radius,
    WORLDPAINT_OT_pipette,
    WORLDPAINT_OT_move_region,
    WORLDPAINT_OT_stretch_region,
    WORLDPAINT_OT_gradient,
    WORLDPAINT_OT_blur,
    WORLDPAINT_OT_generate_village,
    WORLDPAINT_OT_learn_village,
    WORLDPAINT_OT_export_encyclopedia,
    WORLDPAINT_OT_show_interest,
    WORLDPAINT_OT_embed_roads,
    WORLDPAINT_OT_build_waterfall,
    WORLDPAINT_OT_load_village_preset,
    WORLDPAINT_OT_add_village_event,
    WORLDPAINT_OT_remove_village_event,
    WORLDPAINT_OT_move_village_event,
    WORLDPAINT_OT_apply_sketch,
    *display.classes,
    *sketch_draw.classes,
    *arrangement.classes,
    *variety.classes,
    *variety_tools.classes,
    *variety_texture.classes,
    *world.classes,
    *world_fill.classes,
    *place.classes,
    *drag.classes,
)

_register_classes, _unregister_classes = bpy.utils.register_classes_factory(_classes)


def register():
    _register_classes()
    sketch_draw.add_overlay()
    variety_texture.add_save_handler()
    snap.add_handlers()


def unregister():
    snap.remove_handlers()
    variety_texture.remove_save_handler()
    sketch_draw.remove_overlay()
    variety_tools.remove_overlays()
    _unregister_classes()
