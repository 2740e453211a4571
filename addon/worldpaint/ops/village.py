"""Villages on arbitrary terrain (thesis ch. 3): Generate Village grows a village by its growth scenario, Show
Interest paints where a building type would like to stand, and the scenario list's own operators (load a preset,
add, remove and reorder events).

Generate Village runs the engine on a worker thread with a progress bar and Esc to cancel (see ``background``); it
replaces the current village's objects (see ``bridge.village``), and is one undo step; a generation that builds
nothing changes nothing and says why.
"""

import json

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from ..bridge import WorldPaintError, engine, files, place, terrain, village
from ..props.village import CRITERIA, EVENT_KINDS
from .background import BackgroundOperator
from .common import ListMoveOperator, TerrainProperty, reports_errors, setting


class VillageInputs(TerrainProperty):
    """Operator properties of a village's setting; unset, the Village panel's."""

    region_object: StringProperty(
        name="Region", description="Closed curve object bounding the village (empty: the panel's region)"
    )
    whole_terrain: BoolProperty(
        name="Whole Terrain", default=False, description="Use the whole terrain, whatever the panel's region"
    )
    encyclopedia_path: StringProperty(
        name="Encyclopedia", subtype='FILE_PATH', options={'ANIMATABLE', 'PATH_SUPPORTS_BLEND_RELATIVE'},
        description="Building encyclopedia JSON file (empty: the panel's, else the shipped one)",
    )
    cell: FloatProperty(name="Grid Cell", default=0.0, min=0.0, unit='LENGTH', description="0: the panel's")

    def region_curve(self, context):
        if self.whole_terrain:
            return None
        if self.region_object:
            obj = context.scene.objects.get(self.region_object)
            if obj is None:
                raise WorldPaintError(f"No object named '{self.region_object}' in the scene to bound the village")
            return obj
        return context.scene.worldpaint.village.region

    def read_setting(self, context):
        """(terrain object, engine terrain, region, encyclopedia, grid cell), checked."""
        settings = context.scene.worldpaint.village
        terrain_obj = terrain.terrain_object(context, self.terrain)
        heightfield = terrain.engine_terrain(context, terrain_obj)
        region = village.village_region(self.region_curve(context), heightfield)
        terrain.check_region_on_terrain(heightfield, region, "village")
        encyclopedia = village.scene_encyclopedia(settings, self.encyclopedia_path)
        cell = self.cell if self.cell > 0.0 else settings.cell
        return terrain_obj, heightfield, region, encyclopedia, cell


class WORLDPAINT_OT_generate_village(BackgroundOperator, VillageInputs, bpy.types.Operator):
    """Grow a village on the terrain by the growth scenario: roads, parcels and houses (Esc cancels)"""

    bl_idname = "worldpaint.generate_village"
    bl_label = "Generate Village"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Generating village"

    preset: StringProperty(name="Preset", description="Scenario preset to grow (empty: the panel's scenario list)")
    scenario_path: StringProperty(
        name="Scenario File", subtype='FILE_PATH', options={'ANIMATABLE', 'PATH_SUPPORTS_BLEND_RELATIVE'},
        description="Growth scenario JSON file {\"events\": [...]} (empty: the panel's scenario list)",
    )
    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed (unset: the panel's seed)")

    def _prepare(self, context):
        """Validates the inputs and extracts what the engine needs; changes nothing."""
        settings = context.scene.worldpaint.village
        terrain_obj, heightfield, region, encyclopedia, cell = self.read_setting(context)
        if self.preset and self.scenario_path:
            raise WorldPaintError("Give a scenario preset or a scenario file, not both")
        if self.preset:
            events = village.preset_events(self.preset)
        elif self.scenario_path:
            events = village.scenario_file_events(self.scenario_path)
        else:
            events = village.list_events(settings.events)
        scenario = village.scenario_json(events)
        roads = village.existing_roads(settings)
        self._terrain_obj, self._heightfield = terrain_obj, heightfield
        self._parcels_as_curves = settings.parcels_as_curves
        self._arguments = (heightfield, region, scenario, setting(self, "seed", settings.seed))
        self._call = dict(
            encyclopedia=encyclopedia.text,
            connections=village.connection_points(settings, region, roads),
            existing_roads=roads or None,
            cell=cell,
            parcel_cell=min(settings.parcel_cell, cell),
            **village.surroundings(settings),
        )

    def _compute(self, progress):
        return engine.generate_village(*self._arguments, progress=progress, **self._call)

    def _apply(self, context, result):
        if village.builds_nothing(result, self._parcels_as_curves):
            # an empty village would leave an empty collection and unused materials behind, and replace the
            # current village by nothing
            self.report({'WARNING'}, village.nothing_built(result.report))
            return {'CANCELLED'}
        built = village.build_village(context.scene, result, self._terrain_obj, self._heightfield,
                                      self._parcels_as_curves)
        info, warnings = village.summary(built, result.report)
        context.scene.worldpaint.village.report = info
        self.report({'INFO'}, info)
        for warning in warnings:
            self.report({'WARNING'}, warning)
        return {'FINISHED'}


class WORLDPAINT_OT_learn_village(BackgroundOperator, VillageInputs, bpy.types.Operator):
    """Learn a village type from the real village of the place inside the region: a search grows villages on the
    same terrain until they have its figures (Esc stops it and keeps the best type so far)"""

    bl_idname = "worldpaint.learn_village"
    bl_label = "Learn Village"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Learning village"
    keeps_best_on_cancel = True

    name: StringProperty(name="Name", description="Name of the learned village type (unset: the panel's)")
    minutes: FloatProperty(name="Minutes", default=0.0, min=0.0, description="Longest search (0: the panel's)")
    max_evaluations: IntProperty(name="Evaluations", default=0, min=0,
                                 description="Most candidate village types the search grows (0: as many as grow "
                                 "about 60,000 buildings, so that the same village and seed learn the same type)")
    seed: IntProperty(name="Seed", default=1, min=0, description="Random seed of the search")

    def _prepare(self, context):
        settings = context.scene.worldpaint.village
        if settings.region is None and not self.region_object:
            raise WorldPaintError("Learn Village: set the Village panel's region to a closed curve around the real "
                                  "village to learn from")
        _, heightfield, region, encyclopedia, cell = self.read_setting(context)
        centres, orientations, roads = place.real_village(context.scene, region)
        name = self.name or settings.learn_name or f"like {self.region_curve(context).name}"
        if name in encyclopedia.village_types:
            raise WorldPaintError(f"Learn Village: the encyclopedia already has a village type '{name}': give the "
                                  "learned type another name")
        if settings.learn_base_type and settings.learn_base_type not in encyclopedia.village_types:
            raise WorldPaintError(f"Learn Village: '{settings.learn_base_type}' is not a village type of the "
                                  f"encyclopedia (it has {', '.join(sorted(encyclopedia.village_types))})")
        minutes = self.minutes if self.minutes > 0.0 else settings.learn_minutes
        self._name = name
        self._arguments = (heightfield, region, centres, orientations, roads)
        self._call = dict(encyclopedia=encyclopedia.text, base_type=settings.learn_base_type or None, name=name,
                          seed=self.seed, max_evaluations=self.max_evaluations, max_seconds=60.0 * minutes, cell=cell,
                          parcel_cell=min(settings.parcel_cell, cell), **village.surroundings(settings))

    def _compute(self, progress):
        return engine.learn_village(*self._arguments, progress=progress, **self._call)

    def _apply(self, context, result):
        settings = context.scene.worldpaint.village
        village.keep_encyclopedia(settings, result["encyclopedia"])
        settings.encyclopedia_path = ""
        village.fill_list(settings.events, json.loads(result["scenario"])["events"])
        real = result["real"]
        held_out = result["held_out_objective"]
        info = (f"'{self._name}' learned from {real['buildings']} buildings, starting from '{result['base_type']}'; "
                f"figures {result['objective']:.2f} bands from the real ones"
                + (f" ({held_out:.2f} at new seeds)" if held_out is not None else "")
                + f" (start {result['base_objective']:.2f}); "
                f"{result['evaluations']} villages in {result['seconds']:.0f} s"
                + ("; stopped early, best so far kept" if result["stopped_early"] else ""))
        settings.learn_report = info
        self.report({'INFO'}, info)
        return {'FINISHED'}


class WORLDPAINT_OT_export_encyclopedia(bpy.types.Operator):
    """Write the building encyclopedia the .blend holds (with its learned village types) to a JSON file"""

    bl_idname = "worldpaint.export_encyclopedia"
    bl_label = "Export Encyclopedia"

    filepath: StringProperty(subtype='FILE_PATH', options={'SKIP_SAVE'})
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    def invoke(self, context, _event):
        if not self.filepath:
            self.filepath = "encyclopedia.json"
        context.window_manager.fileselect_add(self)
        return {'RUNNING_MODAL'}

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint.village
        if settings.encyclopedia_text is None:
            raise WorldPaintError("Export Encyclopedia: the .blend holds no encyclopedia (Learn Village makes one)")
        text = settings.encyclopedia_text.as_string()
        path = files.absolute_path(self.filepath, "encyclopedia file")
        try:
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        except OSError as exc:
            raise WorldPaintError(f"Cannot write the encyclopedia to '{self.filepath}': {exc}") from exc
        self.report({'INFO'}, f"Encyclopedia written to {path}")
        return {'FINISHED'}


class WORLDPAINT_OT_show_interest(VillageInputs, bpy.types.Operator):
    """Color the terrain by how much a building type would like to stand there (Solid mode, Attribute color)"""

    bl_idname = "worldpaint.show_interest"
    bl_label = "Show Interest"
    bl_options = {'REGISTER', 'UNDO'}

    village_type: StringProperty(name="Village Type", description="Empty: the panel's")
    building: StringProperty(name="Building", description="Empty: the panel's")
    criterion: EnumProperty(
        name="Criterion", items=(("SCENE", "Panel Setting", "The criterion chosen in the Village panel"),) + CRITERIA,
        default="SCENE",
    )

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint.village
        terrain_obj, heightfield, region, encyclopedia, cell = self.read_setting(context)
        if terrain_obj.mode == 'EDIT':
            raise WorldPaintError(f"The terrain '{terrain_obj.name}' is in Edit Mode: leave it first")
        village_type = (self.village_type or settings.interest_village_type).strip()
        building = (self.building or settings.interest_building).strip()
        if village_type not in encyclopedia.village_types:
            raise WorldPaintError(f"Unknown village type '{village_type}' (the encyclopedia has "
                                  f"{', '.join(sorted(encyclopedia.village_types))})")
        if building not in encyclopedia.buildings:
            raise WorldPaintError(f"Unknown building type '{building}' (the encyclopedia has "
                                  f"{', '.join(sorted(encyclopedia.buildings))})")
        criterion = settings.interest_criterion if self.criterion == "SCENE" else self.criterion
        current = village.current_village(context.scene)
        roads = village.existing_roads(settings) + village.village_roads(current)
        values = engine.village_interest(
            heightfield, region, village.terrain_vertices_xy(terrain_obj), village_type, building,
            None if criterion == "INTEREST" else criterion, encyclopedia=encyclopedia.text,
            buildings=village.village_buildings(current), roads=roads or None, cell=cell,
            **village.surroundings(settings),
        )

        village.write_interest(terrain_obj, values)
        space = context.space_data
        if space is not None and space.type == 'VIEW_3D' and space.shading.type == 'SOLID':
            space.shading.color_type = 'VERTEX'
        name = dict((key, label) for key, label, _ in CRITERIA)[criterion]
        self.report({'INFO'}, f"{name} of a {building} in a {village_type} village: from {values.min():.2f} to "
                              f"{values.max():.2f} (blue below 0, white 0, red to yellow above)")
        return {'FINISHED'}


class WORLDPAINT_OT_load_village_preset(bpy.types.Operator):
    """Fill the scenario list with a growth scenario preset"""

    bl_idname = "worldpaint.load_village_preset"
    bl_label = "Load Scenario Preset"
    bl_options = {'REGISTER', 'UNDO'}

    preset: StringProperty(name="Preset", description="Name of the scenario preset")

    @reports_errors
    def execute(self, context):
        events = village.preset_events(self.preset)
        settings = context.scene.worldpaint.village
        village.fill_list(settings.events, events)
        settings.active_event_index = 0
        self.report({'INFO'}, f"Loaded '{village.preset_label(self.preset)}': {len(events)} events")
        return {'FINISHED'}


class WORLDPAINT_OT_add_village_event(bpy.types.Operator):
    """Add an event to the growth scenario after the active one"""

    bl_idname = "worldpaint.add_village_event"
    bl_label = "Add Scenario Event"
    bl_options = {'REGISTER', 'UNDO'}

    kind: EnumProperty(name="Event", items=EVENT_KINDS, default="GENERATE")
    name: StringProperty(name="Type", description="Village type or building type (empty: the default one)")
    count: IntProperty(name="Count", default=1, min=1)

    def execute(self, context):
        settings = context.scene.worldpaint.village
        events = settings.events
        item = events.add()
        item.kind = self.kind
        if self.kind == 'VILLAGE_TYPE':
            item.village_type = self.name or item.village_type
        else:
            item.building, item.count = self.name or item.building, self.count
        target = min(settings.active_event_index + 1, len(events) - 1) if len(events) > 1 else 0
        events.move(len(events) - 1, target)
        settings.active_event_index = target
        return {'FINISHED'}


class WORLDPAINT_OT_remove_village_event(bpy.types.Operator):
    """Remove the active event of the growth scenario"""

    bl_idname = "worldpaint.remove_village_event"
    bl_label = "Remove Scenario Event"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        settings = context.scene.worldpaint.village
        if not 0 <= settings.active_event_index < len(settings.events):
            self.report({'ERROR'}, "No scenario event to remove")
            return {'CANCELLED'}
        settings.events.remove(settings.active_event_index)
        settings.active_event_index = max(0, min(settings.active_event_index, len(settings.events) - 1))
        return {'FINISHED'}


class WORLDPAINT_OT_move_village_event(ListMoveOperator, bpy.types.Operator):
    """Move the active event of the growth scenario up or down"""

    bl_idname = "worldpaint.move_village_event"
    bl_label = "Move Scenario Event"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        return self.move_active(context.scene.worldpaint.village, "events", "active_event_index")
