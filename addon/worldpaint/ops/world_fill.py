"""The World panel's operators: paint the world's map on the terrain, place village sites, and Fill World.

Fill World runs the world command line (``python -m worldpaint_engine.world``) in a process of its own, with
Blender's Python: it starts a local Dask cluster of worker processes (which a process that has imported bpy could
not spawn), writes the tile set whole or not at all, and says on stdout how far it is. Blender stays responsive, the
header shows the tiles done, Esc stops the run (the tile set and the scene stay as they were), and the finished
world is loaded into the scene, nearest the camera first.
"""

import importlib.util
import os
import re
import subprocess
import sys
import tempfile
import threading
import time

import bpy
import numpy as np
from bpy.props import IntProperty, StringProperty

from ..bridge import WorldPaintError, engine, files, points, regions, snap, terrain, village, world, world_map
from .common import report_errors

ENGINE_COMMAND = "worldpaint_engine.world"
ERROR_PREFIX = f"python -m {ENGINE_COMMAND}: error: "
PROGRESS = re.compile(r"^tile (\d+) of (\d+)$")


def map_to_paint(context):
    """(the scene's settings, the terrain, the swatches' palette) for painting the map; a clear error without a
    terrain or a palette color."""
    settings = context.scene.worldpaint
    terrain_obj = terrain.terrain_object(context)
    if not len(settings.palette):
        raise WorldPaintError("The palette has no colors: learn or add the colors to paint the map with")
    return settings, terrain_obj, world_map.swatch_palette(settings)


class WORLDPAINT_OT_paint_world_map(bpy.types.Operator):
    """Paint the world's map on the terrain in Vertex Paint: a color attribute with one swatch per palette color
    (swatch k paints color k); Fill World fills each painted part with its color"""

    bl_idname = "worldpaint.paint_world_map"
    bl_label = "Paint World Map"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        def run():
            settings, terrain_obj, palette = map_to_paint(context)
            made = settings.world.map_attribute not in terrain_obj.data.color_attributes
            world_map.ensure_map(terrain_obj, settings, settings.world.map_attribute)
            if context.window is not None and context.mode == 'OBJECT':
                for obj in context.selected_objects:
                    obj.select_set(False)
                terrain_obj.select_set(True)
                context.view_layer.objects.active = terrain_obj
                bpy.ops.object.mode_set(mode='VERTEX_PAINT')
            context.tool_settings.vertex_paint.palette = palette
            first = f", all {settings.palette[world_map.active_index(settings)].name} to begin with" if made else ""
            self.report({'INFO'}, f"Paint the map '{settings.world.map_attribute}' on '{terrain_obj.name}' with the "
                                  f"swatches of '{palette.name}'{first}")
            return {'FINISHED'}

        return report_errors(self, run)


class WORLDPAINT_OT_paint_map_in_curves(bpy.types.Operator):
    """Paint the world's map inside the selected closed curves with a palette color (as drawn outlines of a forest,
    a lake shore, fields)"""

    bl_idname = "worldpaint.paint_map_in_curves"
    bl_label = "Paint Inside Curves"
    bl_options = {'REGISTER', 'UNDO'}

    color: StringProperty(name="Color", description="The palette color to paint (empty: the active one)")

    def execute(self, context):
        def run():
            settings, terrain_obj, _ = map_to_paint(context)
            names = [entry.name for entry in settings.palette]
            name = self.color or names[world_map.active_index(settings)]
            if name not in names:
                raise WorldPaintError(f"The palette has no color '{name}' (it has {', '.join(names)})")
            curves = [obj for obj in context.selected_objects if obj.type == 'CURVE']
            if not curves:
                raise WorldPaintError("Select the closed curves to paint inside")
            shapes = [regions.curve_polygon(obj) for obj in curves]
            painted = world_map.paint_inside(terrain_obj, settings, shapes, names.index(name))
            self.report({'INFO'}, f"Painted {painted:,} vertices of the map with {name}")
            return {'FINISHED'}

        return report_errors(self, run)


class WORLDPAINT_OT_paint_map_from_image(bpy.types.Operator):
    """Paint the world's map from an image laid over the terrain's extent (a land-use map): each vertex takes the
    palette color whose swatch is nearest the pixel under it (set the swatches to the image's colors first)"""

    bl_idname = "worldpaint.paint_map_from_image"
    bl_label = "Paint from Image"
    bl_options = {'REGISTER', 'UNDO'}

    image: StringProperty(name="Image", description="The image of the map, in the file's images")

    def execute(self, context):
        def run():
            settings, terrain_obj, _ = map_to_paint(context)
            image = bpy.data.images.get(self.image)
            if image is None:
                raise WorldPaintError(f"No image '{self.image}' in the file: open the map's image first")
            counts = world_map.paint_from_image(terrain_obj, settings, image)
            shares = ", ".join(f"{entry.name} {n / max(counts.sum(), 1):.0%}"
                               for entry, n in zip(settings.palette, counts, strict=True) if n)
            self.report({'INFO'}, f"Painted the map from '{image.name}': {shares}")
            return {'FINISHED'}

        return report_errors(self, run)

    def invoke(self, context, _event):
        return context.window_manager.invoke_props_dialog(self)

    def draw(self, _context):
        self.layout.prop_search(self, "image", bpy.data, "images")


class WORLDPAINT_OT_add_village_site(bpy.types.Operator):
    """Add a village site at the 3D cursor, on the terrain: Fill World grows its village there before the tiles,
    joined to the other sites by roads"""

    bl_idname = "worldpaint.add_village_site"
    bl_label = "Add Village Site"
    bl_options = {'REGISTER', 'UNDO'}

    village_type: StringProperty(name="Village Type", default="farming",
                                 description="A village type of the scene's encyclopedia")
    buildings: IntProperty(name="Buildings", default=20, min=1, max=2000)

    def execute(self, context):
        def run():
            terrain_obj = terrain.terrain_object(context)
            x, y, z = context.scene.cursor.location
            height = snap.surface(terrain_obj).heights(np.array([[x, y]]))[0]
            if height != height:  # NaN: off the terrain
                raise WorldPaintError(f"The 3D cursor ({x:.1f}, {y:.1f}) is not over the terrain '{terrain_obj.name}'"
                                      ": put it where the village should grow")
            site = bpy.data.objects.new("Village Site", None)
            site.empty_display_type = 'CONE'
            site.empty_display_size = 15.0
            site.rotation_euler = (3.14159265, 0.0, 0.0)  # the cone points down at the ground
            site.location = (x, y, float(height) + 15.0)
            points.worldpaint_child(context.scene, world_map.SITES_COLLECTION).objects.link(site)
            props = site.worldpaint_site
            props.is_site, props.village_type, props.buildings = True, self.village_type, self.buildings
            props.seed = len(world_map.village_sites(context.scene)) - 1
            for obj in context.selected_objects:
                obj.select_set(False)
            site.select_set(True)
            context.view_layer.objects.active = site
            return {'FINISHED'}

        return report_errors(self, run)


class WORLDPAINT_OT_set_site_type(bpy.types.Operator):
    """Grow a village of this type at the active village site"""

    bl_idname = "worldpaint.set_site_type"
    bl_label = "Set Village Type"
    bl_options = {'REGISTER', 'UNDO'}

    village_type: StringProperty(name="Village Type", description="A village type of the scene's encyclopedia")

    def execute(self, context):
        def run():
            site = context.object
            if site is None or not site.worldpaint_site.is_site:
                raise WorldPaintError("Select a village site (Add Village Site makes one)")
            types = village.known_types(context.scene.worldpaint.village)[0]
            if self.village_type not in types:
                raise WorldPaintError(f"The encyclopedia has no village type '{self.village_type}' (it has "
                                      f"{', '.join(types)})")
            site.worldpaint_site.village_type = self.village_type
            return {'FINISHED'}

        return report_errors(self, run)


def engine_message(stderr, site_names):
    """The world command line's one-line error as the panel says it: its village sites named by their empties."""
    lines = [line for line in stderr.strip().splitlines() if line.strip()]
    text = lines[-1] if lines else "the run ended without a word"
    text = text.removeprefix(ERROR_PREFIX)
    text = re.sub(r"--villages \S+: ", "", text)
    for k, name in sorted(site_names.items(), reverse=True):
        text = re.sub(rf"\b(village )?site {k}\b", f"the village site '{name}'", text)
    return text[:1].upper() + text[1:]


class WORLDPAINT_OT_fill_world(bpy.types.Operator):
    """Fill the whole terrain with the map painted on it (or the active color), growing the village sites and the
    roads between them first, on a local Dask cluster; then load the world, nearest the camera first"""

    bl_idname = "worldpaint.fill_world"
    bl_label = "Fill World"
    bl_options = {'REGISTER', 'UNDO'}

    def _start(self, context):
        """Writes the inputs and starts the command line; raises before anything runs for input it would refuse."""
        if importlib.util.find_spec("distributed") is None:
            raise WorldPaintError("Fill World runs on a local Dask cluster, and Dask is not installed in Blender's "
                                  f"Python: install it with '{sys.executable} -m pip install \"dask[distributed]\"'")
        settings = context.scene.worldpaint.world
        self._out = os.path.normpath(files.absolute_path(settings.directory, "tile set folder"))
        self._inputs = tempfile.TemporaryDirectory(prefix="worldpaint-world-")
        try:
            args, self._site_names = world_map.write_inputs(context, self._inputs.name)
        except Exception:
            self._inputs.cleanup()
            raise
        args += ["--seed", str(settings.seed), "--out", self._out, "--overwrite", "--progress-lines"]
        if settings.tile > 0.0:
            args += ["--tile", repr(settings.tile)]
        if settings.workers > 0:
            args += ["--workers", str(min(settings.workers, os.cpu_count() or 1))]
        # the add-on's packages (the engine among them) are on Blender's path, not on the new process's
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p and os.path.isdir(p)))
        self._done, self._total, self._began = 0, 0, time.monotonic()
        self._stderr = open(os.path.join(self._inputs.name, "stderr.txt"), "w+", encoding="utf-8")  # noqa: SIM115
        self._process = subprocess.Popen([sys.executable, "-m", ENGINE_COMMAND, *args], cwd=self._inputs.name,
                                         env=env, stdout=subprocess.PIPE, stderr=self._stderr, text=True)
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        for line in self._process.stdout:
            found = PROGRESS.match(line.strip())
            if found:
                self._done, self._total = int(found[1]), int(found[2])

    def _end_process(self, cancel=False):
        """Waits for the command line (stopping it first on ``cancel``: it then removes what it had written) and
        returns its exit code and its error line."""
        if cancel:
            self._process.terminate()
        try:
            code = self._process.wait(timeout=60 if cancel else None)
        except subprocess.TimeoutExpired:
            self._process.kill()
            code = self._process.wait()
        self._reader.join()
        self._process.stdout.close()
        self._stderr.seek(0)
        error = self._stderr.read()
        self._stderr.close()
        self._inputs.cleanup()
        return code, error

    def _finish(self, context, code, error):
        if code != 0:
            raise WorldPaintError(f"Fill World: {engine_message(error, self._site_names)}")
        scene = context.scene
        settings = scene.worldpaint.world
        manifest = engine.world_manifest(self._out)
        world.remove_world(self._out)  # the world filled here before: the new tile set replaced it
        collection = world.world_collection(scene, self._out, manifest)
        world.load_villages(collection, self._out, manifest)
        for entry in world.tiles_to_load(manifest, world.view_centre(scene, manifest), 0.0, set()):
            world.load_tile(scene, collection, self._out, entry, settings.display, settings.cull_distance,
                            settings.lod_distance)
        villages = manifest.get("villages")
        settings.report = (f"{manifest['instances']:,} instances in {len(manifest['tiles'])} tiles in "
                           f"{time.monotonic() - self._began:.0f} s")
        if villages:
            settings.report += f"; {villages['buildings']} buildings in {villages['count']} villages"
        self.report({'INFO'}, f"Filled the world in '{self._out}': {settings.report}")
        return {'FINISHED'}

    def invoke(self, context, _event):
        def start():
            self._start(context)
            wm = context.window_manager
            self._timer = wm.event_timer_add(0.2, window=context.window)
            wm.progress_begin(0, 1)
            wm.modal_handler_add(self)
            return {'RUNNING_MODAL'}

        return report_errors(self, start)

    def execute(self, context):
        def run():
            self._start(context)
            return self._finish(context, *self._end_process())

        return report_errors(self, run)

    def _stop(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        if context.area is not None:
            context.area.header_text_set(None)

    def modal(self, context, event):
        if event.type == 'ESC':
            self._stop(context)
            self._end_process(cancel=True)
            self.report({'WARNING'}, "Fill World cancelled; the tile set and the scene are as they were")
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        if self._process.poll() is None:
            fraction = self._done / self._total if self._total else 0.0
            context.window_manager.progress_update(fraction)
            if context.area is not None:
                doing = f"tile {self._done} of {self._total}" if self._total else "growing the villages and roads"
                context.area.header_text_set(f"Fill World: {doing} (Esc to cancel)")
            return {'RUNNING_MODAL'}
        self._stop(context)
        outcome = report_errors(self, lambda: self._finish(context, *self._end_process()))
        return outcome if outcome == {'FINISHED'} else {'CANCELLED'}


classes = (WORLDPAINT_OT_paint_world_map, WORLDPAINT_OT_paint_map_in_curves, WORLDPAINT_OT_paint_map_from_image,
           WORLDPAINT_OT_add_village_site, WORLDPAINT_OT_set_site_type, WORLDPAINT_OT_fill_world)
