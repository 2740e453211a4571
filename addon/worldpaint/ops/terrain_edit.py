"""Terrain that adapts (thesis 4.4.2): Embed Roads cuts road curves into the terrain as a shape key, with level
carriageways and cut and fill banks, and re-seats what stands on the changed ground. One undo step."""

import bpy
import numpy as np
from bpy.props import FloatProperty, StringProperty

from ..bridge import WorldPaintError, terrain, terrain_edit
from ..bridge.engine import engine
from .common import TerrainProperty, report_errors


class WORLDPAINT_OT_embed_roads(TerrainProperty, bpy.types.Operator):
    """Cut roads into the terrain: level carriageways, with banks blending into the slope (a shape key)"""

    bl_idname = "worldpaint.embed_roads"
    bl_label = "Embed Roads"
    bl_options = {'REGISTER', 'UNDO'}

    roads: StringProperty(
        name="Roads", description="Collection of road curves (empty: the panel's, else the selected curves, else "
                                  "the current village's roads)",
    )
    width: FloatProperty(name="Carriageway", default=0.0, min=0.0, unit='LENGTH', description="0: the panel's")
    bank_width: FloatProperty(name="Banks", default=-1.0, min=-1.0, unit='LENGTH', description="-1: the panel's")

    def execute(self, context):
        return report_errors(self, lambda: self._embed(context))

    def _embed(self, context):
        settings = context.scene.worldpaint.terrain_edit
        obj = terrain.terrain_object(context, self.terrain)
        if obj.mode == 'EDIT':
            raise WorldPaintError(f"The terrain '{obj.name}' is in Edit Mode: leave it first")
        collection = settings.roads
        if self.roads:
            collection = bpy.data.collections.get(self.roads)
            if collection is None:
                raise WorldPaintError(f"No collection named '{self.roads}' to take the roads from")
        roads = terrain_edit.roads_to_embed(context, collection)
        width = self.width if self.width > 0.0 else settings.width
        bank_width = self.bank_width if self.bank_width >= 0.0 else settings.bank_width
        standing = terrain_edit.Standing(context.scene)
        with terrain_edit.without_key(obj, terrain_edit.EMBED_ROADS_KEY):
            heightfield = terrain.engine_terrain(context, obj)
        vertices = terrain_edit.basis_world(obj)
        reseated = standing.points() if settings.reseat else vertices[:0, :2]
        points = np.vstack([vertices[:, :2], reseated])
        result = engine().embed_roads(
            heightfield, roads, points, width, bank_width, use_heights=settings.use_curve_heights,
            smoothing=settings.smoothing if settings.smoothing > 0.0 else None,
        )
        dz = result["displacement"]
        terrain_edit.write_shape_key(obj, terrain_edit.EMBED_ROADS_KEY, dz[:len(vertices)])
        if settings.reseat:
            standing.reseat(dz[len(vertices):])
        changed = dz[:len(vertices)]
        self.report({'INFO'}, f"Embedded {len(roads)} road(s) in '{obj.name}': cut {max(-changed.min(), 0.0):.2f} m, "
                              f"fill {max(changed.max(), 0.0):.2f} m (shape key '{terrain_edit.EMBED_ROADS_KEY}')")
        return {'FINISHED'}
