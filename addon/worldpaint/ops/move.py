"""Move Region: the content of a region moves and adapts to its new ground and neighbours (seed §5.4).

From a script, ``offset`` says how far. From the viewport, the region follows the mouse over the terrain: each
position is recomputed from the scene as it was when the drag began (so what still fits never flickers), on a worker
thread that always takes the newest position; click or Enter confirms, Esc or the right button cancels.
"""

import bpy
import numpy as np
from bpy.props import FloatVectorProperty, StringProperty

from ..bridge import WorldPaintError, engine, view
from .background import REFRESH_SECONDS, LatestWorker
from .common import RegionSynthesisProperties, SceneContent, active_color, report_errors, report_missing


class MoveJob:
    """The move of one region's content, computed for any offset from the same extracted scene."""

    def __init__(self, operator, context):
        settings = context.scene.worldpaint
        self.content = SceneContent(context, operator.terrain)
        self.source = operator.destination(context, self.content.terrain_obj)
        found = self.content.instances
        inside = engine.region_contains(self.source, found.positions) & ~found.locked
        if not inside.any():
            raise WorldPaintError("Nothing to move: the region holds no synthesized instances")
        if operator.color:
            self.color = active_color(context, operator.color).json
        else:
            # the moved content's own statistics, learned once for the whole drag
            try:
                self.color = self.content.learn(self.source, "moved", ["slope"])
            except engine.NothingToLearn:
                self.color = None  # only an arrangement's elements: they move rigidly, with nothing to follow
        self.synthesis = operator.synthesis_arguments(settings)

    def compute(self, offset):
        return engine.move_region(self.content.engine_scene(), color=self.color, source=self.source, offset=offset,
                                  **self.synthesis)


class WORLDPAINT_OT_move_region(RegionSynthesisProperties, bpy.types.Operator):
    """Move the content of a region; it adapts to the terrain and the content at its new place"""

    bl_idname = "worldpaint.move_region"
    bl_label = "Move Region"
    bl_options = {'REGISTER', 'UNDO'}

    offset: FloatVectorProperty(name="Offset", size=2, subtype='XYZ', unit='LENGTH')
    color: StringProperty(name="Color", description="Palette color whose statistics the moved content follows "
                                                    "(empty: the statistics of the moved content itself)")

    def execute(self, context):
        def run():
            job = MoveJob(self, context)
            return self._finish(context, job, job.compute(self.offset))

        return report_errors(self, run)

    def _finish(self, context, job, moved):
        applied = job.content.apply(context, moved.edit)
        self.report({'INFO'}, f"Moved {moved.moved} instances: {moved.displaced} adapted to their new place, "
                              f"{moved.reborn} replaced")
        if moved.lost:
            self.report({'WARNING'}, f"{moved.lost} instances found no place their statistics allow")
        if moved.stayed:
            self.report({'WARNING'}, f"{moved.stayed} instances stayed where they were: the move would put them "
                                     "off the terrain")
        report_missing(self, applied)
        return {'FINISHED'}

    def invoke(self, context, event):
        def start():
            self._job = MoveJob(self, context)
            # the drag starts where the mouse first meets the terrain
            self._start = view.terrain_under_mouse(context, self._job.content.terrain_obj, event)
            self._worker = LatestWorker(self._job.compute)
            wm = context.window_manager
            self._timer = wm.event_timer_add(REFRESH_SECONDS, window=context.window)
            wm.modal_handler_add(self)
            return {'RUNNING_MODAL'}

        return report_errors(self, start)

    def modal(self, context, event):
        if event.type == 'MOUSEMOVE':
            hit = view.terrain_under_mouse(context, self._job.content.terrain_obj, event)
            if hit is not None and self._start is None:
                self._start = hit
            if hit is not None:
                self.offset = (hit.x - self._start.x, hit.y - self._start.y)
                self._worker.request(tuple(self.offset))
        elif event.type == 'TIMER':
            self._show(context, self._worker.take())
        elif event.type in {'LEFTMOUSE', 'RET', 'NUMPAD_ENTER'} and event.value == 'PRESS':
            return self._confirm(context)
        elif event.type in {'ESC', 'RIGHTMOUSE'}:
            self._end(context)
            self._job.content.restore(context)
            return {'CANCELLED'}
        return {'RUNNING_MODAL'}

    def _show(self, context, taken):
        if taken is None:
            return
        offset, moved = taken
        if isinstance(moved, Exception):
            return
        self._job.content.restore(context)
        self._job.content.apply(context, moved.edit)
        if context.area is not None:
            context.area.header_text_set(f"Move: {offset[0]:.1f}, {offset[1]:.1f} m — {moved.displaced} adapted "
                                         "(click to confirm, Esc to cancel)")

    def _confirm(self, context):
        self._end(context)
        self._job.content.restore(context)
        offset = np.array(self.offset, dtype=np.float64)
        return report_errors(self, lambda: self._finish(context, self._job, self._job.compute(offset)))

    def cancel(self, context):
        self._end(context)
        self._job.content.restore(context)

    def _end(self, context):
        self._worker.close()
        context.window_manager.event_timer_remove(self._timer)
        if context.area is not None:
            context.area.header_text_set(None)
