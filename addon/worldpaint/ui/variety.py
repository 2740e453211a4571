"""The Model Variety panel: decompose the active mesh, see its components, add texture edits, generate variants."""

import bpy

from ..ops import variety_tools
from .panel import MainSubpanel, enlarged


class WORLDPAINT_UL_components(bpy.types.UIList):
    def draw_item(self, _context, layout, _data, item, _icon, _active_data, _active_propname, _index):
        row = layout.row(align=True)
        row.label(text=item.name, icon='MESH_DATA')
        row.label(text=f"{item.faces} faces")
        row.label(text=f"joined to {item.regions}")
        row.prop(item, "repeat", text="Repeat")
        row.prop(item, "pick", text="")


class WORLDPAINT_UL_texture_edits(bpy.types.UIList):
    def draw_item(self, _context, layout, _data, item, _icon, _active_data, _active_propname, index):
        row = layout.row(align=True)
        row.prop(item, "image", text="")
        row.operator("worldpaint.paint_texture_edit", text="", icon='BRUSH_DATA').index = index


class WORLDPAINT_PT_variety(MainSubpanel, bpy.types.Panel):
    bl_label = "Model Variety"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        obj = context.view_layer.objects.active
        if obj is None or obj.type != 'MESH':
            layout.label(text="Select a low-poly mesh (a tree, a rock, a house)")
            return
        settings = obj.worldpaint_variety
        box = layout.box()
        box.prop(settings, "source")
        if settings.source == 'ATTRIBUTE':
            box.prop(settings, "attribute")
        box.prop(settings, "root")
        decompose = enlarged(box.column()).operator("worldpaint.decompose_model", icon='MOD_EXPLODE')
        decompose.source, decompose.attribute, decompose.root = settings.source, settings.attribute, settings.root
        if settings.source == 'SEAMS':
            box.operator("worldpaint.cut_model", icon='SCULPTMODE_HLT').object = obj.name
        if settings.source == 'ATTRIBUTE':
            box.operator("worldpaint.mark_component", icon='FACESEL').object = obj.name
        if not settings.components:
            return
        row = layout.row()
        row.label(text=settings.graph, icon='NODETREE')
        row.operator("worldpaint.component_graph", text="", icon='HIDE_OFF' if variety_tools.shown(obj) else
                     'HIDE_ON', depress=variety_tools.shown(obj)).object = obj.name
        layout.template_list("WORLDPAINT_UL_components", "", settings, "components", settings, "active_component",
                             rows=3)
        layout.label(text="Edit copies of a part in its collection to make variants", icon='INFO')
        self.draw_texture(layout, settings)
        box = layout.box()
        row = box.row(align=True)
        row.prop(settings, "count")
        row.prop(settings, "seed")
        col = enlarged(box.column(), invoke=True)
        generate = col.operator("worldpaint.generate_variants", icon='OUTLINER_OB_GROUP_INSTANCE')
        generate.count, generate.seed = settings.count, settings.seed
        generate.probability = settings.texture_probability
        picked = col.operator("worldpaint.generate_variants", text="Assemble Picks", icon='HAND')
        picked.by_hand = True
        if settings.report:
            box.label(text=settings.report)
        if settings.texture_report:
            box.label(text=settings.texture_report)
        if settings.generated is not None:
            box.label(text="Paint with them: set a category's Variants to this collection")
            box.prop(settings, "generated")


    @staticmethod
    def draw_texture(layout, settings):
        """Texture variety (seed §5): the base texture, the texture edits painted over it, how often variants show
        them, and the atlases the last generation packed them into."""
        box = layout.box()
        box.label(text="Texture Variety", icon='TEXTURE')
        box.prop(settings, "base_image")
        row = box.row()
        row.template_list("WORLDPAINT_UL_texture_edits", "", settings, "texture_edits", settings,
                          "active_texture_edit", rows=2)
        col = row.column(align=True)
        col.operator("worldpaint.add_texture_edit", text="", icon='ADD')
        col.operator("worldpaint.remove_texture_edit", text="", icon='REMOVE')
        if not settings.texture_edits:
            box.label(text="New Texture Edit copies the base texture: paint details on it", icon='INFO')
            return
        box.prop(settings, "texture_probability")
        for item in settings.atlases:
            if item.image is not None:
                box.label(text=f"{item.image.name}: {item.edits}", icon='IMAGE_DATA')


classes = (WORLDPAINT_UL_components, WORLDPAINT_UL_texture_edits, WORLDPAINT_PT_variety)
