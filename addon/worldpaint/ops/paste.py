"""Paste Color: synthesize the active color in a region, replacing the synthesized points already there.

Run from a script (``exec``) the synthesis runs to completion. Run from the UI (``invoke``) it runs on a worker thread
(the engine releases the GIL) while a modal handler shows the progress and cancels on Esc; the scene is only changed
once the result is complete, so a cancelled paste changes nothing.
"""

import threading
from dataclasses import dataclass

import bpy
import numpy as np
from bpy.props import FloatProperty, IntProperty, StringProperty

from ..bridge import instances, points, regions, terrain
from ..bridge.engine import engine
from .common import RegionProperties, TerrainProperty, active_color, report_errors


@dataclass
class PasteJob:
    """Everything the synthesis needs, extracted from the scene before it starts."""

    terrain_obj: object
    heightfield: object
    color_name: str
    region: dict
    arguments: dict


class WORLDPAINT_OT_paste_color(RegionProperties, TerrainProperty, bpy.types.Operator):
    """Paste new instances with the statistics of the active color into the region (Esc cancels)"""

    bl_idname = "worldpaint.paste_color"
    bl_label = "Paste Color"
    bl_options = {'REGISTER', 'UNDO'}

    color: StringProperty(name="Color", description="Palette color to paste (empty: the active one)")
    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed (unset: the panel's seed)")
    influence_radius: FloatProperty(
        name="Influence", default=-1.0, description="Region of influence width (negative: the panel's setting)"
    )

    def execute(self, context):
        def run():
            job = self._prepare(context)
            result = _with_progress(context, lambda progress: _synthesize(job, progress))
            return self._apply(context, job, result)

        return report_errors(self, run)

    def invoke(self, context, _event):
        def start():
            self._job = self._prepare(context)
            self._fraction = 0.0
            self._cancel = False
            self._outcome = None
            self._worker = threading.Thread(target=self._work, daemon=True)
            self._worker.start()
            wm = context.window_manager
            self._timer = wm.event_timer_add(0.1, window=context.window)
            wm.progress_begin(0.0, 1.0)
            wm.modal_handler_add(self)
            return {'RUNNING_MODAL'}

        return report_errors(self, start)

    def _work(self):
        def progress(fraction):
            self._fraction = fraction
            return not self._cancel

        try:
            self._outcome = ("ok", _synthesize(self._job, progress))
        except Exception as exc:  # noqa: BLE001 - handed to the main thread, which reports it
            self._outcome = ("error", exc)

    def modal(self, context, event):
        if event.type == 'ESC':
            self._cancel = True
        if event.type != 'TIMER':
            return {'RUNNING_MODAL'}
        context.window_manager.progress_update(self._fraction)
        if context.area is not None:
            context.area.header_text_set(f"Pasting color: {self._fraction:.0%} (Esc to cancel)")
        if self._worker.is_alive():
            return {'RUNNING_MODAL'}
        self._finish(context)
        kind, value = self._outcome or ("error", RuntimeError("the synthesis stopped without a result"))

        def raise_error():
            raise value

        if kind == "error":
            return report_errors(self, raise_error)
        return report_errors(self, lambda: self._apply(context, self._job, value))

    def cancel(self, context):
        self._cancel = True
        self._worker.join()
        self._finish(context)

    def _finish(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        if context.area is not None:
            context.area.header_text_set(None)

    def _prepare(self, context):
        """Validates the inputs and extracts what the engine needs; changes nothing."""
        scene = context.scene
        settings = scene.worldpaint
        eng = engine()
        terrain_obj = terrain.terrain_object(context, self.terrain)
        entry = active_color(context, self.color)
        selected = [o for o in context.selected_objects if o != terrain_obj and not instances.is_worldpaint_object(o)]
        region = regions.region_for(
            context, self.resolved_region_mode(context), objects=selected, use_bounds=True, **self.region_kwargs()
        )
        heightfield = terrain.engine_terrain(context, terrain_obj)
        terrain.check_region_on_terrain(heightfield, region, "destination")

        summary = eng.color_summary(entry.json)
        categories = instances.merged_categories(settings, summary["categories"])
        existing = instances.scene_instances(scene, categories, exclude=[terrain_obj])
        seed = self.seed if self.properties.is_property_set("seed") else settings.seed
        if self.influence_radius >= 0.0:
            influence = self.influence_radius
        else:
            influence = None if settings.auto_influence else settings.influence_radius
        arguments = dict(color=entry.json, region=region, seed=seed, influence_radius=influence,
                         **existing.engine_arrays())
        return PasteJob(terrain_obj, heightfield, entry.name, region, arguments)

    def _apply(self, context, job, result):
        """Replaces the synthesized points inside the region with the result, and sets up the instancers."""
        scene = context.scene
        eng = engine()
        new_by_category = _split_by_category(result)
        dropped = sum(n for _, _, n in new_by_category.values())
        for category, obj in instances.point_cloud_objects(scene).items():
            co, rotation, scale, prototype = instances.point_cloud_arrays(obj)
            keep = ~eng.region_contains(job.region, np.ascontiguousarray(co[:, :2])) if len(co) else np.zeros(0, bool)
            if category in new_by_category:
                (nco, nrot, nscale, nproto), _, _ = new_by_category.pop(category)
                points.write_points(
                    obj,
                    np.concatenate([co[keep], nco]),
                    np.concatenate([rotation[keep], nrot]),
                    np.concatenate([scale[keep], nscale]),
                    np.concatenate([prototype[keep], nproto]),
                )
            elif not keep.all():
                points.write_points(obj, co[keep], rotation[keep], scale[keep], prototype[keep])
        for category, (columns, _, _) in new_by_category.items():
            points.write_points(points.point_cloud_object(scene, category), *columns)
        missing = []
        for category, obj in instances.point_cloud_objects(scene).items():
            collection = points.instancer_collection(obj)
            if collection is None:
                collection = points.prototype_collection(scene, category, exclude=[job.terrain_obj])
                if collection is None:
                    missing.append(category)
            points.set_instancer(obj, collection, job.terrain_obj)
        count = len(result["positions"]) - dropped
        self.report({'INFO'}, f"Pasted {count} instances of '{job.color_name}'")
        empty = sorted(set(c["name"] for c in eng.color_summary(job.arguments["color"])["categories"])
                       - set(result["categories"][i]["name"] for i in np.unique(result["category_index"])))
        if empty:
            self.report({'WARNING'}, f"Nothing pasted for {', '.join(empty)}: the example had none on slopes (or, "
                                     "for a color with a height preference, heights) like the destination's")
        if missing:
            self.report({'WARNING'}, f"No collection or mesh to instance for: {', '.join(missing)}")
        return {'FINISHED'}


def _synthesize(job, progress):
    return engine().synthesize(job.heightfield, progress=progress, **job.arguments)


def _split_by_category(result):
    """{category: ((co, rotation, scale, prototype), index, dropped)} of a synthesis result, z on the terrain."""
    names = [c["name"] for c in result["categories"]]
    xy = result["positions"]
    z = result["heights"]
    on_terrain = np.isfinite(z)
    out = {}
    for index, name in enumerate(names):
        chosen = result["category_index"] == index
        mask = chosen & on_terrain
        if not chosen.any():
            continue
        co = np.column_stack([xy[mask], z[mask]])
        columns = (co, result["rotations"][mask], result["scales"][mask], result["prototype"][mask])
        out[name] = (columns, index, int(chosen.sum() - mask.sum()))
    return out


def _with_progress(context, compute):
    """Runs compute(progress) with Blender's progress indicator when there is a window manager."""
    wm = context.window_manager
    if wm is None:
        return compute(None)

    def progress(fraction):
        wm.progress_update(fraction)
        return True

    wm.progress_begin(0.0, 1.0)
    try:
        return compute(progress)
    finally:
        wm.progress_end()
