"""What the operators share: region properties, the scene settings they default to, and error reporting."""

import functools

import numpy as np
from bpy.props import EnumProperty, FloatProperty, FloatVectorProperty, IntProperty, StringProperty

from ..bridge import WorldPaintError, curves, edits, engine, instances, points, regions, scene_maps, terrain
from ..props import REGION_MODES

OPERATOR_REGION_MODES = (
    (("SCENE", "Scene Setting", "The region mode chosen in the WorldPaint panel"),)
    + REGION_MODES
    + (
        ("RECT", "Rectangle", "The rectangle given by Rect Min and Rect Max"),
        ("CIRCLE", "Circle", "The circle given by Circle Center and Circle Radius"),
    )
)


class RegionProperties:
    """Operator properties choosing a region; by default the scene's region setting and the selection."""

    region_mode: EnumProperty(name="Region", items=OPERATOR_REGION_MODES, default="SCENE")
    rect_min: FloatVectorProperty(name="Rect Min", size=2, subtype='XYZ', unit='LENGTH')
    rect_max: FloatVectorProperty(name="Rect Max", size=2, subtype='XYZ', unit='LENGTH')
    circle_center: FloatVectorProperty(name="Circle Center", size=2, subtype='XYZ', unit='LENGTH')
    circle_radius: FloatProperty(
        name="Circle Radius", default=0.0, min=0.0, unit='LENGTH', description="0 uses the panel's radius"
    )
    curve: StringProperty(name="Curve", description="Closed curve object of the region (empty: the selected one)")

    def resolved_region_mode(self, context):
        if self.region_mode == "SCENE":
            return context.scene.worldpaint.region_mode
        return self.region_mode

    def destination(self, context, terrain_obj):
        """The region to work in: by the chosen mode, from the selection's bounds (without the terrain and
        WorldPaint's own objects)."""
        selected = [o for o in context.selected_objects
                    if o != terrain_obj and not instances.is_worldpaint_object(o)]
        return regions.region_for(context, self.resolved_region_mode(context), objects=selected, use_bounds=True,
                                  **self.region_kwargs())

    def region_kwargs(self):
        return {
            "rect_min": tuple(self.rect_min),
            "rect_max": tuple(self.rect_max),
            "center": tuple(self.circle_center),
            "radius": self.circle_radius,
            "curve_name": self.curve,
        }


FLOAT_MAX = 3.4e38  # Blender stores an infinity typed in a float field as the largest float, 3.4028e38


def number_text(value):
    """A number for a message: "nan", "inf" for what Blender stores of an infinity, else as it is."""
    return "nan" if value != value else f"{'-' if value < 0 else ''}inf" if abs(value) >= FLOAT_MAX else f"{value:g}"


def setting(operator, name, default):
    """The operator's property when it was given, else ``default`` (the panel's setting), which must be finite when
    it is a number (a script can store a NaN there: Blender's min and max do not stop it)."""
    if operator.properties.is_property_set(name):
        return getattr(operator, name)
    if isinstance(default, float) and not abs(default) < FLOAT_MAX:
        label = operator.properties.bl_rna.properties[name].name
        raise WorldPaintError(f"{label} in the panel must be a finite number, got {number_text(default)}")
    return default


class SynthesisProperties:
    """The seed and the region of influence of an operator that synthesizes; unset, the panel's."""

    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed (unset: the panel's seed)")
    influence_radius: FloatProperty(
        name="Influence", default=-1.0, description="Region of influence width (negative: the panel's setting)"
    )

    def synthesis_arguments(self, settings, color=None):
        """The engine's ``seed`` and ``influence_radius`` (None: the color's own interaction radius), and the
        ``iterations_per_instance`` of the palette ``color`` painted when it sets them."""
        seed = setting(self, "seed", settings.seed)
        if self.influence_radius >= 0.0:
            influence = self.influence_radius
        elif color is not None and color.influence_radius >= 0.0:
            influence = color.influence_radius
        else:
            influence = None if settings.auto_influence else settings.influence_radius
        arguments = {"seed": seed, "influence_radius": influence}
        if color is not None and color.iterations_per_instance > 0.0:
            arguments["iterations_per_instance"] = color.iterations_per_instance
        return arguments


class TerrainProperty:
    terrain: StringProperty(name="Terrain", description="Terrain object (empty: the one picked in the panel)")


class RegionSynthesisProperties(RegionProperties, SynthesisProperties, TerrainProperty):
    """The properties of an operator that synthesizes in a region of the terrain."""


def check_numbers(operator):
    """Refuses a float property of ``operator`` that is not a finite number, naming it: Blender's min and max let a
    NaN through, and store an infinity as the largest float."""
    given = operator.properties
    for prop in given.bl_rna.properties:
        if prop.type != 'FLOAT':
            continue
        value = getattr(given, prop.identifier)
        values = list(value) if prop.is_array else [value]
        if not all(abs(v) < FLOAT_MAX for v in values):  # false for a NaN too
            shown = ", ".join(number_text(v) for v in values)
            raise WorldPaintError(f"{prop.name} must be {'finite numbers' if prop.is_array else 'a finite number'}, "
                                  f"got {f'({shown})' if prop.is_array else shown}")


def report_errors(operator, action):
    """Runs ``action`` (which changes nothing before it has validated everything) once the operator's numbers are
    checked; errors become UI reports."""
    try:
        check_numbers(operator)
        return action()
    except WorldPaintError as exc:
        operator.report({'ERROR'}, str(exc))
        return {'CANCELLED'}
    except engine.engine_error() as exc:
        if engine.is_cancelled(exc):
            operator.report({'WARNING'}, "Cancelled; the scene is unchanged")
        else:
            operator.report({'ERROR'}, str(exc))
        return {'CANCELLED'}


def reports_errors(execute):
    """Makes an operator's ``execute`` report its errors instead of raising them (see ``report_errors``)."""

    @functools.wraps(execute)
    def reporting(self, context):
        return report_errors(self, lambda: execute(self, context))

    return reporting


class ListMoveOperator:
    """An operator moving the active item of a list one place up or down."""

    direction: EnumProperty(name="Direction", items=(("UP", "Up", ""), ("DOWN", "Down", "")), default="UP")

    def move_active(self, owner, items, active_index):
        """Moves the item ``owner.<active_index>`` of ``owner.<items>`` and keeps it active; cancelled at an end."""
        collection, index = getattr(owner, items), getattr(owner, active_index)
        target = index - 1 if self.direction == 'UP' else index + 1
        if not (0 <= index < len(collection) and 0 <= target < len(collection)):
            return {'CANCELLED'}
        collection.move(index, target)
        setattr(owner, active_index, target)
        return {'FINISHED'}


def active_color(context, name=""):
    """The palette entry of the given name, else the active one."""
    palette = context.scene.worldpaint.palette
    if len(palette) == 0:
        raise WorldPaintError("The palette is empty: learn a color first (or import a palette)")
    if name:
        entry = palette.get(name)
        if entry is None:
            raise WorldPaintError(f"No color named '{name}' in the palette")
        return entry
    index = context.scene.worldpaint.active_color_index
    return palette[min(max(index, 0), len(palette) - 1)]


def color_pair(context, first, second, missing):
    """The palette entries named ``first`` (empty: the active one) and ``second`` (empty: the panel's To Color; an
    error saying ``missing`` when that is empty too)."""
    start = active_color(context, first)
    second = second or context.scene.worldpaint.gradient_end
    if not second:
        raise WorldPaintError(missing)
    return start, active_color(context, second)


class SceneContent:
    """What a tool reads of the scene before the engine runs: the terrain object, its heightfield, every instance
    of the scene's categories (hand-placed objects locked, point-cloud points editable) and every path and contour
    (hand-drawn curves locked, synthesized ones editable). The ``colors`` a tool paints (``engine.ColorSummary``)
    add their categories and the maps made in the scene that they follow.

    With the panel's Active Layer Only, a tool changes the active layer alone: the content of the other layers is
    held as if hand-placed (it conditions the result, nothing removes or moves it) and what the tool would add of
    their categories is left out."""

    def __init__(self, context, terrain_name="", colors=()):
        scene = context.scene
        settings = scene.worldpaint
        self.layer = settings.active_layer if settings.layer_only else None
        self.terrain_obj = terrain.terrain_object(context, terrain_name)
        self.heightfield = terrain.engine_terrain(context, self.terrain_obj, scene_maps.used_by(colors))
        self.categories = instances.all_categories(scene, [c for color in colors for c in color.categories])
        self.instances = instances.scene_instances(scene, self.categories, exclude=[self.terrain_obj])
        self.structures = curves.scene_structures(scene, self.categories, exclude=[self.terrain_obj])
        self._engine_scene = None

    def learn(self, region, name, maps):
        """The color (JSON) of this content inside ``region``, with the terrain ``maps``."""
        return engine.learn_color(self.engine_scene(), region, name, maps)

    def engine_scene(self):
        """The engine's Scene of this content (made once; the tools read it and return edits of it)."""
        if self._engine_scene is None:
            instance_arrays = self.instances.engine_arrays()
            structure_arrays = self.structures.engine_arrays()
            if self.layer is not None:
                held = np.array([not self.in_layer(c["name"]) for c in self.categories], dtype=bool)
                if len(instance_arrays["category_index"]):
                    instance_arrays["locked"] = instance_arrays["locked"] | held[instance_arrays["category_index"]]
                for lines in structure_arrays.values():
                    for line in lines:
                        line["locked"] = line["locked"] or bool(held[line["category"]])
            self._engine_scene = engine.scene(self.heightfield, instance_arrays, structure_arrays)
        return self._engine_scene

    def in_layer(self, category):
        """Whether the tools may change ``category`` (a name): always, unless they act on the active layer only."""
        if self.layer is None:
            return True
        return any(c["name"] == category and c["layer"] == self.layer for c in self.categories)

    def layer_categories(self, names):
        """Those of the category ``names`` the tools may change; an error when that leaves none."""
        allowed = [name for name in names if self.in_layer(name)]
        if names and not allowed:
            raise WorldPaintError(f"None of {', '.join(names)} is in the active layer '{self.layer}' (Active Layer "
                                  "Only is on)")
        return allowed

    def apply(self, context, edit):
        """Writes an edit (``engine.Edit``) of this content to the point clouds and the synthesized curves."""
        if self.layer is not None:
            edit = edit.restricted([self.in_layer(name) for name in edit.category_names])
        applied = edits.apply_edit(context.scene, self.instances, edit, self.terrain_obj)
        applied.lines_added, applied.lines_removed = curves.apply_structures(
            context.scene, self.structures, edit, self.terrain_obj, self.heightfield
        )
        return applied

    def restore(self, context):
        """Puts the point clouds and curves back as this content read them (after a cancelled live edit)."""
        edits.restore_clouds(context.scene, self.instances)
        curves.restore_structures(context.scene, self.structures, self.terrain_obj, self.heightfield)


def report_missing(operator, applied):
    if applied.missing:
        empty = [f"the collection '{c.name}' shows nothing" for c in map(points.empty_named_collection,
                                                                         applied.missing) if c is not None]
        why = f" ({'; '.join(empty)})" if empty else ""
        operator.report({'WARNING'}, f"No collection or mesh to instance for: {', '.join(applied.missing)}{why}")
