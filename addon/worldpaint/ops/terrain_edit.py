"""Terrain that adapts (thesis ch. 4): Embed Roads cuts road curves into the terrain, with level carriageways and cut
and fill banks; Build Waterfall turns controller curves into a coherent waterfall scene, with water meshes, the
terrain deformed around them and river rocks synthesized from a palette color (else the built-in river rocks). Each
change to the terrain is a shape key named after its operator, what stands on the changed ground is re-seated, and
each run is one undo step."""

import bpy
import numpy as np
from bpy.props import FloatProperty, IntProperty, StringProperty

from ..bridge import WorldPaintError, engine, terrain, terrain_edit
from .background import BackgroundOperator
from .common import TerrainProperty, reports_errors

UNMOVED = 1e-6  # metres: a terrain change below this is no change


def editable_terrain(context, name):
    """The terrain object, out of Edit Mode (its mesh is read and given a shape key)."""
    obj = terrain.terrain_object(context, name)
    if obj.mode == 'EDIT':
        raise WorldPaintError(f"The terrain '{obj.name}' is in Edit Mode: leave it first")
    return obj


def collection_named(name, default, what):
    """The collection called ``name``, else ``default`` when no name is given."""
    if not name:
        return default
    collection = bpy.data.collections.get(name)
    if collection is None:
        raise WorldPaintError(f"No collection named '{name}' to take the {what} from")
    return collection


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

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint.terrain_edit
        obj = editable_terrain(context, self.terrain)
        collection = collection_named(self.roads, settings.roads, "roads")
        roads, left_out = terrain_edit.roads_to_embed(context, collection)
        width = self.width if self.width > 0.0 else settings.width
        bank_width = self.bank_width if self.bank_width >= 0.0 else settings.bank_width
        standing = terrain_edit.Standing(context.scene)
        with terrain_edit.without_key(obj, terrain_edit.EMBED_ROADS_KEY):
            heightfield = terrain.engine_terrain(context, obj)
        vertices = terrain_edit.basis_world(obj)
        reseated = standing.points() if settings.reseat else vertices[:0, :2]
        points = np.vstack([vertices[:, :2], reseated])
        embedding = engine.embed_roads(
            heightfield, roads, points, width, bank_width, use_heights=settings.use_curve_heights,
            smoothing=settings.smoothing if settings.smoothing > 0.0 else None,
        )
        dz = embedding.displacement
        terrain_edit.write_shape_key(obj, terrain_edit.EMBED_ROADS_KEY, dz[:len(vertices)])
        if settings.reseat:
            standing.reseat(dz[len(vertices):], "roads")
        changed = dz[:len(vertices)]
        self.report({'INFO'}, f"Embedded {len(roads)} road(s) in '{obj.name}': cut {max(-changed.min(), 0.0):.2f} m, "
                              f"fill {max(changed.max(), 0.0):.2f} m (shape key '{terrain_edit.EMBED_ROADS_KEY}')")
        if left_out:
            self.report({'WARNING'}, f"Left out: {'; '.join(left_out)}")
        return {'FINISHED'}


class WORLDPAINT_OT_build_waterfall(BackgroundOperator, TerrainProperty, bpy.types.Operator):
    """Build a waterfall scene from the curves marked as Contact, Free-fall or Pool: water meshes, and the terrain
    deformed to hold them (a shape key; Esc cancels)"""

    bl_idname = "worldpaint.build_waterfall"
    bl_label = "Build Waterfall"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Building waterfall"

    controllers: StringProperty(
        name="Controllers", description="Collection of controller curves (empty: the panel's, else every marked curve)",
    )
    seed: IntProperty(name="Seed", default=0, min=0, description="Seed of the subdivision (unset: the panel's)")
    rock_color: StringProperty(
        name="Rock Color", description="Palette color of the river rocks (unset: the panel's; empty there: the "
                                       "built-in river rocks)",
    )

    def _prepare(self, context):
        settings = context.scene.worldpaint.terrain_edit
        obj = editable_terrain(context, self.terrain)
        collection = collection_named(self.controllers, settings.controllers, "controllers")
        controllers = terrain_edit.waterfall_controllers(context, collection)
        name = self.rock_color if self.properties.is_property_set("rock_color") else settings.rock_color
        rock_color = terrain_edit.rock_color_json(context.scene, name)
        self._standing = terrain_edit.Standing(context.scene, exclude=(terrain_edit.ROCK_CATEGORY,))
        with terrain_edit.without_key(obj, terrain_edit.WATERFALL_KEY):
            heightfield = terrain.engine_terrain(context, obj)
        self._vertices = terrain_edit.basis_world(obj)
        points = np.vstack([self._vertices[:, :2], self._standing.points()])
        seed = self.seed if self.properties.is_property_set("seed") else settings.waterfall_seed
        self._terrain_obj = obj
        self._keep_dry = settings.keep_dry
        self._controllers = controllers
        self._arguments = (heightfield, controllers, np.ascontiguousarray(points), seed)
        self._call = dict(min_slope=settings.min_slope, overhang=settings.overhang, falloff=settings.falloff,
                          max_width=settings.max_width, rock_color=rock_color)

    def _compute(self, progress):
        if progress is not None and not progress(0.0):
            return None
        return engine.build_waterfall(*self._arguments, **self._call)

    def _apply(self, context, waterfall):
        n = len(self._vertices)
        offsets = np.column_stack([waterfall.horizontal[:n], waterfall.displacement[:n]])
        moved = max(np.abs(offsets).max(initial=0.0), np.abs(waterfall.displacement).max(initial=0.0)) > UNMOVED
        if not (moved or len(waterfall.water.triangles) or len(waterfall.rocks)):
            self.report({'WARNING'}, f"The waterfall built nothing, the scene is unchanged: its "
                                     f"{len(waterfall.segments)} segments on {waterfall.arcs} arcs hold no water, "
                                     "no rock and no change to the terrain; check the controller curves")
            return {'CANCELLED'}
        # a terrain the waterfall leaves as it is gets no shape key, unless one of an earlier run must be replaced
        if moved or terrain_edit.has_shape_key(self._terrain_obj, terrain_edit.WATERFALL_KEY):
            terrain_edit.write_shape_key(self._terrain_obj, terrain_edit.WATERFALL_KEY, offsets)
            self._standing.reseat(waterfall.displacement[n:], "waterfall")
        dry = self._standing.keep_dry(waterfall.is_water[n:]) if self._keep_dry else 0
        terrain_edit.build_water(context.scene, waterfall.water)
        terrain_edit.build_rocks(context.scene, waterfall, self._terrain_obj)
        invalid = [s for s in waterfall.segments if not s.valid]
        self.report({'INFO'}, f"Waterfall: {len(waterfall.segments)} segments on {waterfall.arcs} arcs, "
                              f"{len(waterfall.rocks)} rocks, {dry} instances taken out of the water")
        if invalid:
            curves = sorted({self._controllers[s.controller]["name"] for s in invalid})
            self.report({'WARNING'}, f"{len(invalid)} segments lie outside the valid range of their type (slope and "
                                     f"flow do not match a contact or free-fall; the water's 'invalid' attribute "
                                     f"marks them): check {', '.join(repr(c) for c in curves)}")
        return {'FINISHED'}
