"""File › Import › WorldPaint Place: a real place (OpenStreetMap layers, an elevation model, a tree inventory) as a
scene the tools understand (see ``bridge.place``).

The files are chosen together in the file browser, or given as properties from a script: a chosen file is read by
its extension, .asc, .hgt and .tif as the elevation model (one), .csv as the tree inventory (one), any other as a map
layer (GeoJSON). The engine reads and projects them on a worker thread with a progress bar and Esc to cancel (see
``background``), from a script to completion; the scene is built only once the engine has returned, so a bad file, a
cancel or the time limit changes nothing, and the import is one undo step. When the scene already has a place, the
import is given its origin, so that the two line up.
"""

import os

import bpy
from bpy.props import BoolProperty, CollectionProperty, FloatProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ImportHelper

from ..bridge import WorldPaintError, engine, engine_place, files, place, terrain
from .background import BackgroundOperator
from .common import setting

ELEVATION_EXTENSIONS = (".asc", ".hgt", ".tif", ".tiff")
INVENTORY_EXTENSIONS = (".csv",)
FILE_FILTER = "*.geojson;*.json;*.asc;*.hgt;*.tif;*.tiff;*.csv"


def sort_files(paths):
    """(map layers, elevation models, tree inventories) of file paths, by their extensions."""
    layers, elevations, inventories = [], [], []
    for path in paths:
        extension = os.path.splitext(path)[1].lower()
        if extension in ELEVATION_EXTENSIONS:
            elevations.append(path)
        elif extension in INVENTORY_EXTENSIONS:
            inventories.append(path)
        else:
            layers.append(path)
    return layers, elevations, inventories


def one_of(paths, what):
    """The one path of ``paths`` (None when there is none); a clear error when there are more."""
    if len(paths) > 1:
        names = ", ".join(os.path.basename(p) for p in paths)
        raise WorldPaintError(f"A place has one {what}: {len(paths)} were given ({names})")
    return paths[0] if paths else None


class WORLDPAINT_OT_import_place(BackgroundOperator, ImportHelper, bpy.types.Operator):
    """Import a real place: OpenStreetMap layers (GeoJSON), an elevation model (.asc, .hgt, .tif) and a tree
    inventory (.csv) as terrain, buildings, roads, areas and trees the tools understand (Esc cancels)"""

    bl_idname = "worldpaint.import_place"
    bl_label = "Import WorldPaint Place"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Importing place"

    filename_ext = ".geojson"
    filter_glob: StringProperty(default=FILE_FILTER, options={'HIDDEN'})
    # ImportHelper's path, said to take "//" paths: they are resolved (see ``files``)
    filepath: StringProperty(name="File Path", description="A file of the place", maxlen=1024, subtype='FILE_PATH',
                             options={'SKIP_SAVE', 'HIDDEN', 'PATH_SUPPORTS_BLEND_RELATIVE'})
    files: CollectionProperty(type=bpy.types.OperatorFileListElement, options={'HIDDEN', 'SKIP_SAVE'})
    directory: StringProperty(subtype='DIR_PATH', options={'HIDDEN', 'SKIP_SAVE'})
    layers: StringProperty(name="Map Layers", options={'SKIP_SAVE'},
                           description="OpenStreetMap layers (GeoJSON files), separated by ';'")
    elevation: StringProperty(name="Elevation Model", subtype='FILE_PATH', options={'SKIP_SAVE'},
                              description="An ESRI ASCII grid (.asc), SRTM tile (.hgt) or GeoTIFF (.tif)")
    inventory: StringProperty(name="Tree Inventory", subtype='FILE_PATH', options={'SKIP_SAVE'},
                              description="A CSV of trees: x, y (m) or lon, lat, species, dbh or height")
    cell: FloatProperty(name="Terrain Cell", default=0.0, min=0.0, unit='LENGTH',
                        description="Spacing of the terrain's vertices (0: the elevation model's; unset: the panel's)")
    margin: FloatProperty(name="Margin", default=200.0, min=0.0, unit='LENGTH',
                          description="How far the terrain reaches beyond the layers (unset: the panel's)")
    tree_species: IntProperty(name="Tree Species", default=12, min=1, max=64,
                              description="Categories of the most common species, the others 'Other trees' (unset: "
                                          "the panel's)")
    from_browser: BoolProperty(options={'HIDDEN', 'SKIP_SAVE'})

    def given_paths(self):
        """Every path given: the files chosen in the browser (or ``filepath``), then the properties'."""
        chosen = [os.path.join(self.directory, f.name) for f in self.files if f.name] if self.directory else []
        if not chosen and self.filepath:
            chosen = [self.filepath]
        return chosen

    def sources(self):
        """(map layer paths, elevation model path or None, tree inventory path or None), resolved."""
        layers, elevations, inventories = sort_files(self.given_paths())
        layers += [p.strip() for p in self.layers.split(";") if p.strip()]
        elevations += [self.elevation] if self.elevation else []
        inventories += [self.inventory] if self.inventory else []
        layers = [files.absolute_path(p, "map layer") for p in layers]
        dem = one_of([files.absolute_path(p, "elevation model") for p in elevations], "elevation model")
        trees = one_of([files.absolute_path(p, "tree inventory") for p in inventories], "tree inventory")
        return layers, dem, trees

    def invoke(self, context, event):
        if self.given_paths() or self.layers or self.elevation or self.inventory:
            return BackgroundOperator.invoke(self, context, event)
        self.from_browser = True
        return ImportHelper.invoke(self, context, event)

    def execute(self, context):
        if self.from_browser and context.window is not None:
            # chosen in the file browser: run as invoke does, with the progress in the header and Esc to cancel
            return BackgroundOperator.invoke(self, context, None)
        return BackgroundOperator.execute(self, context)

    def _prepare(self, context):
        """Reads the settings and the scene's place; changes nothing."""
        scene = context.scene
        panel = scene.worldpaint.place
        layers, dem, inventory = self.sources()
        if not (layers or dem or inventory):
            raise WorldPaintError("Choose the place's files: map layers (GeoJSON), an elevation model (.asc, .hgt, "
                                  ".tif) and a tree inventory (.csv), one or more of them")
        cell = setting(self, "cell", panel.cell)
        self._tree_species = setting(self, "tree_species", panel.tree_species)
        self._origin = place.place_origin(scene)
        # without an elevation model of its own, the import stands on the place's terrain, else the scene's
        ground = place.place_terrain(scene) or terrain.optional_terrain_object(context)
        self._ground = ground
        self._heightfield = terrain.engine_terrain(context, ground) if ground is not None and dem is None else None
        self._arguments = dict(geojson_paths=layers, dem_path=dem, inventory_path=inventory, origin=self._origin,
                               cell=cell if cell > 0.0 else None, margin=setting(self, "margin", panel.margin))

    def _compute(self, progress):
        try:
            return engine_place.import_place(**self._arguments, progress=progress)
        except engine.InputError as exc:
            if self._origin is not None and "origin" in str(exc):
                lon, lat = self._origin
                raise WorldPaintError(f"This scene's place is at lon {lon:.4f}, lat {lat:.4f}, and the new files "
                                      f"cannot line up with it: {exc}") from exc
            raise

    def _apply(self, context, imported):
        scene = context.scene
        plan = place.plan(imported, self._tree_species)
        place.check_categories(scene, plan.categories)
        built = place.build_place(scene, imported, plan, self._ground, self._heightfield)
        self.report({'INFO'}, summary(imported, built))
        return {'FINISHED'}


def counted(n, things):
    """"1 building", "2 buildings": ``things`` is the plural."""
    return f"{n} {things[:-1] if n == 1 else things}"


def summary(imported, built):
    """The line an import reports: what it added, what the place held already, the terrain, what it left out."""
    added, already = built.added, built.already
    parts = []
    if imported.buildings.type:
        kinds = ", ".join(f"{n} {name}" for name, n in sorted(
            ((c.name, c.count) for c in built.categories if c.layer == place.LAYERS["building"]
             and c.kind == "distribution"), key=lambda item: -item[1]))
        parts.append(f"{counted(added['buildings'], 'buildings')} ({kinds})")
    for what in ("roads", "waterways", "areas", "trees"):
        if added[what] or already[what]:
            parts.append(counted(added[what], what))
    line = f"Imported {', '.join(parts) or 'nothing new'}"
    if imported.terrain is not None:
        ny, nx = imported.terrain.heights.shape
        line += (f"; terrain {nx} × {ny} vertices {imported.terrain.cell:.1f} m apart"
                 f"{' (replacing the place’s terrain)' if built.terrain_replaced else ''}")
    if sum(already.values()):
        line += f"; already in the place: {', '.join(counted(n, what) for what, n in already.items() if n)}"
    left_out = imported.report.get("left_out", 0) + imported.report.get("unreadable", 0)
    if left_out:
        line += f"; {left_out} features of no kind it places left out"
    return line


classes = (WORLDPAINT_OT_import_place,)
