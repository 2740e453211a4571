"""Paste Color: synthesize the active color in a region, replacing the synthesized points already there."""

import bpy
import numpy as np
from bpy.props import FloatProperty, IntProperty, StringProperty

from ..bridge import instances, points, regions, terrain
from ..bridge.engine import engine
from .common import RegionProperties, TerrainProperty, active_color, report_errors


class WORLDPAINT_OT_paste_color(RegionProperties, TerrainProperty, bpy.types.Operator):
    """Paste new instances with the statistics of the active color into the region"""

    bl_idname = "worldpaint.paste_color"
    bl_label = "Paste Color"
    bl_options = {'REGISTER', 'UNDO'}

    color: StringProperty(name="Color", description="Palette color to paste (empty: the active one)")
    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed (unset: the panel's seed)")
    influence_radius: FloatProperty(
        name="Influence", default=-1.0, description="Region of influence width (negative: the panel's setting)"
    )

    def execute(self, context):
        return report_errors(self, lambda: self._paste(context))

    def _paste(self, context):
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

        result = _with_progress(
            context,
            lambda progress: eng.synthesize(
                heightfield,
                color=entry.json,
                region=region,
                seed=seed,
                influence_radius=influence,
                progress=progress,
                **existing.engine_arrays(),
            ),
        )

        # everything computed: replace the points inside the region, then append the new ones
        new_by_category = _split_by_category(result)
        dropped = sum(n for _, _, n in new_by_category.values())
        clouds = instances.point_cloud_objects(scene)
        for category, obj in clouds.items():
            co, rotation, scale, prototype = instances.point_cloud_arrays(obj)
            keep = ~eng.region_contains(region, np.ascontiguousarray(co[:, :2])) if len(co) else np.zeros(0, bool)
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
            obj = points.point_cloud_object(scene, category)
            points.write_points(obj, *columns)
        missing = []
        for category, obj in instances.point_cloud_objects(scene).items():
            collection = points.instancer_collection(obj)
            if collection is None:
                collection = points.prototype_collection(scene, category, exclude=[terrain_obj])
                if collection is None:
                    missing.append(category)
            points.set_instancer(obj, collection, terrain_obj)
        count = len(result["positions"]) - dropped
        self.report({'INFO'}, f"Pasted {count} instances of '{entry.name}'")
        if missing:
            self.report({'WARNING'}, f"No collection or mesh to instance for: {', '.join(missing)}")
        return {'FINISHED'}


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

