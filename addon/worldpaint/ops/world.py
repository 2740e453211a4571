"""Load a world's tile set into the scene, the tiles nearest the camera first."""

import os

import bpy
from bpy.props import EnumProperty, FloatProperty, StringProperty

from ..bridge import WorldPaintError, engine, points, world
from .common import report_errors


class WORLDPAINT_OT_load_world(bpy.types.Operator):
    """Load a world filled tile by tile (python -m worldpaint_engine.world), the tiles nearest the camera first;
    load again to add the tiles not yet in the scene"""

    bl_idname = "worldpaint.load_world"
    bl_label = "Load World Tiles"
    bl_options = {'REGISTER', 'UNDO'}

    directory: StringProperty(name="Tile Set", subtype='DIR_PATH',
                              description="The folder holding the tile set's manifest.json")
    radius: FloatProperty(name="Radius", default=0.0, min=0.0, unit='LENGTH',
                          description="Only the tiles within this distance of the active camera (0: every tile)")
    display: EnumProperty(name="Display", items=points.DISPLAY_MODES, default='FULL',
                          description="How the viewport shows the loaded instances (a render shows them all)")
    cull_distance: FloatProperty(name="Cull Distance", default=0.0, min=0.0, unit='LENGTH',
                                 description="Instances farther than this from the camera are not shown in the "
                                             "viewport (0: all)")
    lod_distance: FloatProperty(name="LOD Distance", default=0.0, min=0.0, unit='LENGTH',
                                description="With the Bounds or Proxy display, instances within this distance of the "
                                            "camera keep their full mesh (0: none)")

    def _start(self, context):
        """Reads the manifest and lists the tiles to load; raises for a folder that is not a tile set."""
        folder = bpy.path.abspath(self.directory)
        if not os.path.isfile(os.path.join(folder, "manifest.json")):
            raise WorldPaintError(f"No tile set in '{folder}': it has no manifest.json")
        try:
            manifest = engine.world_manifest(folder)
        except (OSError, ValueError) as exc:
            raise WorldPaintError(f"Cannot read the tile set in '{folder}': {exc}") from exc
        scene = context.scene
        centre = world.view_centre(scene, manifest)
        self._folder, self._made, self._instances, self._missing = folder, [], 0, set()
        self._collection = world.world_collection(scene, folder, manifest)
        try:
            self._made.extend(world.load_villages(self._collection, folder, manifest))
        except (OSError, ValueError, KeyError, IndexError) as exc:
            self._undo()
            raise WorldPaintError(f"Cannot read the villages of the tile set in '{folder}': {exc}") from exc
        self._houses = sum(1 for obj in self._made if obj.get(world.VILLAGES_TAG) == "house")
        self._waiting = world.tiles_to_load(manifest, centre, self.radius, world.loaded_tiles(self._collection))
        self._total = len(self._waiting)

    def _load_next(self, context):
        entry = self._waiting.pop(0)
        try:
            count, made, missing = world.load_tile(context.scene, self._collection, self._folder, entry,
                                                   self.display, self.cull_distance, self.lod_distance)
        except (OSError, engine.engine_error()) as exc:
            raise WorldPaintError(f"Cannot read tile {entry['file']}: {exc}") from exc
        self._instances += count
        self._made.extend(made)
        self._missing.update(missing)

    def _finish(self):
        text = f"Loaded {self._total} tiles, {self._instances:,} instances"
        if not self._total:
            text = "Every tile within the radius is already loaded"
        if self._houses:
            text += f", and the villages' {self._houses} houses and roads"
        self.report({'INFO'}, text)
        if self._missing:
            self.report({'WARNING'}, "Nothing to instance for " + ", ".join(sorted(self._missing))
                        + ": add a collection or mesh of that name")
        return {'FINISHED'}

    def _undo(self):
        """Removes what this run loaded (a cancel or an error leaves the scene as it was)."""
        for obj in self._made:
            points.remove_object(obj)
        if not self._collection.objects and not self._collection.children:
            bpy.data.collections.remove(self._collection)

    def invoke(self, context, _event):
        self._interactive = context.window is not None
        if not self.directory:
            context.window_manager.fileselect_add(self)  # calls execute once a folder is chosen
            return {'RUNNING_MODAL'}
        return self.execute(context)

    def execute(self, context):
        def run():
            self._start(context)
            if not getattr(self, "_interactive", False):  # a script or a headless run: all at once
                try:
                    while self._waiting:
                        self._load_next(context)
                except Exception:
                    self._undo()
                    raise
                return self._finish()
            wm = context.window_manager
            self._timer = wm.event_timer_add(0.01, window=context.window)
            wm.progress_begin(0, max(self._total, 1))
            wm.modal_handler_add(self)
            return {'RUNNING_MODAL'}

        return report_errors(self, run)

    def _stop(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)

    def modal(self, context, event):
        if event.type == 'ESC':
            self._stop(context)
            self._undo()
            self.report({'WARNING'}, "Cancelled; the scene is unchanged")
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        if not self._waiting:
            self._stop(context)
            return self._finish()
        try:
            self._load_next(context)
        except WorldPaintError as exc:
            self._stop(context)
            self._undo()
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        done = self._total - len(self._waiting)
        context.window_manager.progress_update(done)
        context.workspace.status_text_set(f"Loading world tiles: {done} of {self._total} (Esc to cancel)")
        return {'RUNNING_MODAL'}


classes = (WORLDPAINT_OT_load_world,)
