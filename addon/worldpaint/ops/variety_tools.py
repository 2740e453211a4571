"""Model variety's drawing tools: Mark Component makes the selected faces a component; Cut Along Curve cuts a model
where the user drew a path (new vertices, their texture coordinates interpolated, the cut marked as seams); Show
Component Graph draws the decomposed model's component graph over it in the viewport."""

import bpy
from bpy.props import StringProperty

from ..bridge import WorldPaintError, variety, variety_cut
from .common import reports_errors
from .variety import model_object

# the graphs drawn, by object name: a second click on the toggle removes one
_overlays = {}


class WORLDPAINT_OT_cut_model(bpy.types.Operator):
    """Cut the mesh along a path drawn as a curve around the part to cut off (a ring around a branch): new vertices
    where the path's plane crosses the faces near it, the cut marked as seams (decompose by Seams to use it)"""

    bl_idname = "worldpaint.cut_model"
    bl_label = "Cut Along Curve"
    bl_options = {'REGISTER', 'UNDO'}

    object: StringProperty(name="Object", description="Mesh to cut (empty: the active object)")
    curve: StringProperty(name="Curve", description="The path (empty: the selected curve)")

    @reports_errors
    def execute(self, context):
        obj = model_object(context, self.object)
        if self.curve:
            curve = context.scene.objects.get(self.curve)
        else:
            curve = next((o for o in context.selected_objects if o.type == 'CURVE'), None)
        if obj.mode != 'OBJECT':
            raise WorldPaintError(f"Leave Edit Mode on '{obj.name}' to cut it")
        cut = variety_cut.cut_along_curve(obj, curve)
        obj.worldpaint_variety.source = 'SEAMS'
        self.report({'INFO'}, f"Cut '{obj.name}': {cut.vertices} new vertices, {cut.seams} seam edges; its seams "
                              f"make {cut.parts} parts (Components: Seams)")
        return {'FINISHED'}


class WORLDPAINT_OT_mark_component(bpy.types.Operator):
    """Make the selected faces one component (a new label in the face attribute wp_component; the model is then
    decomposed by that attribute)"""

    bl_idname = "worldpaint.mark_component"
    bl_label = "Mark Component"
    bl_options = {'REGISTER', 'UNDO'}

    object: StringProperty(name="Object", description="Mesh (empty: the active object)")

    @reports_errors
    def execute(self, context):
        obj = model_object(context, self.object)
        editing = obj.mode == 'EDIT'
        if editing:
            bpy.ops.object.mode_set(mode='OBJECT')  # the selection and the attribute are the mesh's again
        try:
            label, count = variety.mark_selected_faces(obj.data)
        finally:
            if editing:
                bpy.ops.object.mode_set(mode='EDIT')
        settings = obj.worldpaint_variety
        settings.source, settings.attribute = 'ATTRIBUTE', variety.COMPONENT_ATTRIBUTE
        self.report({'INFO'}, f"{count} faces of '{obj.name}' are component {label}")
        return {'FINISHED'}


class WORLDPAINT_OT_component_graph(bpy.types.Operator):
    """Show or hide the component graph over the model: a line from each component's centre to each connecting
    region it shares"""

    bl_idname = "worldpaint.component_graph"
    bl_label = "Show Component Graph"

    object: StringProperty(name="Object", description="Decomposed mesh (empty: the active object)")

    @reports_errors
    def execute(self, context):
        obj = model_object(context, self.object)
        overlay = _overlays.pop(obj.name, None)
        if overlay is not None:
            overlay.remove()
        else:
            settings = obj.worldpaint_variety
            labels = variety.face_labels(obj, settings.source, settings.attribute)
            _overlays[obj.name] = variety_cut.GraphOverlay(variety_cut.graph_lines(obj, labels))
        for area in context.screen.areas if context.screen else ():
            if area.type == 'VIEW_3D':
                area.tag_redraw()
        return {'FINISHED'}


def shown(obj):
    """Whether the component graph of ``obj`` is drawn."""
    return obj.name in _overlays


def remove_overlays():
    for overlay in _overlays.values():
        overlay.remove()
    _overlays.clear()


classes = (WORLDPAINT_OT_mark_component, WORLDPAINT_OT_cut_model, WORLDPAINT_OT_component_graph)
