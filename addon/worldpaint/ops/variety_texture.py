"""Texture edits of a decomposed model (Maréchal et al. §5): New Texture Edit copies the base texture into an image
to paint details on (it becomes the Texture Paint canvas); each edit becomes a texture component when Generate
Variants packs them into atlases and gives the variants' faces the atlases they show. The edits are packed into the
.blend: what was painted on them is packed again as the file is saved."""

import bpy
from bpy.props import IntProperty, StringProperty

from ..bridge import WorldPaintError, variety_texture
from .common import reports_errors
from .variety import model_object


def paint_on(context, image):
    """Makes ``image`` the canvas of Texture Paint's Single Image mode."""
    paint = context.scene.tool_settings.image_paint
    paint.mode = 'IMAGE'
    paint.canvas = image


def edit_index(obj, index):
    """The index of a texture edit (-1: the active one), checked."""
    settings = obj.worldpaint_variety
    index = settings.active_texture_edit if index < 0 else index
    if not 0 <= index < len(settings.texture_edits):
        raise WorldPaintError(f"'{obj.name}' has no texture edit {index + 1}")
    return index


class WORLDPAINT_OT_add_texture_edit(bpy.types.Operator):
    """Copy the base texture into a new image to paint details on (it becomes the Texture Paint canvas); each texture
    edit becomes a texture component that variants show at random"""

    bl_idname = "worldpaint.add_texture_edit"
    bl_label = "New Texture Edit"
    bl_options = {'REGISTER', 'UNDO'}

    object: StringProperty(name="Object", description="Mesh with a base texture (empty: the active object)")
    name: StringProperty(name="Name", description="Name of the new image (empty: the base texture's, numbered)")

    @reports_errors
    def execute(self, context):
        obj = model_object(context, self.object)
        settings = obj.worldpaint_variety
        base = variety_texture.base_image(obj)
        image = variety_texture.edit_copy(base, self.name or f"{base.name} edit {len(settings.texture_edits) + 1}")
        item = settings.texture_edits.add()
        item.image = image
        settings.active_texture_edit = len(settings.texture_edits) - 1
        paint_on(context, image)
        self.report({'INFO'}, f"Paint details on '{image.name}' (Texture Paint, Single Image mode)")
        return {'FINISHED'}


class WORLDPAINT_OT_remove_texture_edit(bpy.types.Operator):
    """Remove a texture edit from the list (its image stays in the file until nothing uses it)"""

    bl_idname = "worldpaint.remove_texture_edit"
    bl_label = "Remove Texture Edit"
    bl_options = {'REGISTER', 'UNDO'}

    object: StringProperty(name="Object", description="Mesh with the texture edits (empty: the active object)")
    index: IntProperty(name="Index", default=-1, min=-1, description="Texture edit to remove (-1: the active one)")

    @reports_errors
    def execute(self, context):
        obj = model_object(context, self.object)
        settings = obj.worldpaint_variety
        index = edit_index(obj, self.index)
        settings.texture_edits.remove(index)
        settings.active_texture_edit = max(0, min(settings.active_texture_edit, len(settings.texture_edits) - 1))
        return {'FINISHED'}


class WORLDPAINT_OT_paint_texture_edit(bpy.types.Operator):
    """Paint on this texture edit: it becomes the Texture Paint canvas (Single Image mode)"""

    bl_idname = "worldpaint.paint_texture_edit"
    bl_label = "Paint Texture Edit"
    bl_options = {'REGISTER', 'UNDO'}

    object: StringProperty(name="Object", description="Mesh with the texture edits (empty: the active object)")
    index: IntProperty(name="Index", default=-1, min=-1, description="Texture edit to paint on (-1: the active one)")

    @reports_errors
    def execute(self, context):
        obj = model_object(context, self.object)
        settings = obj.worldpaint_variety
        index = edit_index(obj, self.index)
        image = settings.texture_edits[index].image
        if image is None:
            raise WorldPaintError(f"Texture edit {index + 1} of '{obj.name}' has no image")
        settings.active_texture_edit = index
        paint_on(context, image)
        return {'FINISHED'}


classes = (WORLDPAINT_OT_add_texture_edit, WORLDPAINT_OT_remove_texture_edit, WORLDPAINT_OT_paint_texture_edit)


@bpy.app.handlers.persistent
def keep_painted_edits(*_args):
    """Before the file is saved: the texture edits keep what was painted on them."""
    variety_texture.keep_painting()


def add_save_handler():
    if keep_painted_edits not in bpy.app.handlers.save_pre:
        bpy.app.handlers.save_pre.append(keep_painted_edits)


def remove_save_handler():
    if keep_painted_edits in bpy.app.handlers.save_pre:
        bpy.app.handlers.save_pre.remove(keep_painted_edits)
