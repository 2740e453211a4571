"""Scene data of WorldPaint: the terrain, the categories, the palette, the region settings and the village.

Everything lives on ``scene.worldpaint`` so it is saved in the .blend with the scene.
"""

import bpy
from bpy.props import (
    BoolProperty,
    CollectionProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

from ..bridge.engine import fidelity_line
from .place import WORLDPAINT_PG_place
from .sketch import WORLDPAINT_PG_sketch, WORLDPAINT_PG_sketch_point, WORLDPAINT_PG_sketch_stroke
from .terrain_edit import WORLDPAINT_PG_terrain_edit, WORLDPAINT_PG_waterfall_controller
from .variety import (
    WORLDPAINT_PG_component,
    WORLDPAINT_PG_texture_atlas,
    WORLDPAINT_PG_texture_edit,
    WORLDPAINT_PG_variety,
)
from .village import WORLDPAINT_PG_village, WORLDPAINT_PG_village_event
from .world import WORLDPAINT_PG_village_site, WORLDPAINT_PG_world

CATEGORY_KINDS = (
    ("distribution", "Distribution", "Instances scattered by the learned statistics"),
    ("graph", "Graph", "Connected elements such as roads or rivers"),
    ("polygon", "Polygon", "Areas such as fields or lakes"),
    ("external", "External", "Context only: conditions others, never synthesized"),
    ("arrangement", "Arrangement", "Elements of a near-regular pattern (paving, tiles, rows) grown from a reference"),
)

PATTERN_STARTS = (
    ("CENTER", "Region Centre", "A pattern pasted where none is around starts at the region's centre"),
    ("CURSOR", "3D Cursor", "A pattern pasted where none is around starts at the 3D cursor"),
)

REGION_MODES = (
    ("SELECTION", "Selection", "The bounding rectangle of the selected objects"),
    ("CURVE", "Closed Curve", "The polygon of the active (selected) closed curve"),
    ("CURSOR", "Cursor Circle", "A circle around the 3D cursor"),
)


class WORLDPAINT_PG_category(bpy.types.PropertyGroup):
    """A category of instances: what it is called, its layer, its kind and its place in the priority order."""

    name: StringProperty(name="Name", description="Instanced collection, mesh data or wp_category of the objects")
    layer: StringProperty(name="Layer", default="default", description="Layer the category belongs to")
    kind: EnumProperty(name="Kind", items=CATEGORY_KINDS, default="distribution")
    priority: IntProperty(
        name="Priority", default=0, description="Lower values are synthesized first and condition the others"
    )
    width: FloatProperty(
        name="Width", default=6.0, min=0.0, soft_max=50.0, unit='LENGTH',
        description="Width of the ribbon a graph category's synthesized roads or rivers are shown with",
    )
    depth: FloatProperty(
        name="Depth", default=0.0, min=0.0, soft_max=10.0, unit='LENGTH',
        description="How deep the middle of the ribbon sinks below the terrain: a river's bed (0: a flat road)",
    )
    variants: PointerProperty(
        name="Variants", type=bpy.types.Collection,
        description="A collection of model variants to instance: each painted instance shows the variant least used "
        "within 50 m of it (none: the category's own prototypes)",
    )


class WORLDPAINT_PG_interaction(bpy.types.PropertyGroup):
    """One row of a color's interaction matrix: how ``category`` depends on ``other`` (a category or a map)."""

    category: StringProperty(name="Category")
    other: StringProperty(name="Other", description="The category or map it depends on")
    how: StringProperty(name="How", description="rdf, oriented rdf, distance to graph, signed distance to polygon, map")
    enabled: BoolProperty(name="Enabled", default=True)


LEARN_RELATIONS = (
    ("AUTO", "Auto", "As the priority order gives: an rdf between distributions, a distance to a road or island, a "
     "map histogram"),
    ("NONE", "None", "Independent: the category is learned and painted as if the other (or the map) were not there"),
    ("ORIENTED", "Oriented", "An rdf that also depends on direction (between distributions)"),
)


class WORLDPAINT_PG_learn_relation(bpy.types.PropertyGroup):
    """A cell of the interaction matrix Learn Color uses: how ``category`` will relate to ``other`` (a category or a
    map); cells not listed are Auto."""

    category: StringProperty(name="Category")
    other: StringProperty(name="Other", description="The category or map it depends on")
    how: EnumProperty(name="How", items=LEARN_RELATIONS, default="AUTO")


class WORLDPAINT_PG_color(bpy.types.PropertyGroup):
    """A learned color: its name, the engine's JSON of it (as painted: without the interactions switched off), the
    JSON as learned, its interaction matrix, the name of its preview image, and its fidelity view: the plot of its
    self-synthesis against its example and the figures of that comparison."""

    name: StringProperty(name="Name")
    json: StringProperty(name="JSON", description="The color as the engine's versioned JSON, as it is painted")
    learned_json: StringProperty(name="Learned JSON", description="The color as learned, every interaction on")
    interactions: CollectionProperty(type=WORLDPAINT_PG_interaction)
    active_interaction_index: IntProperty(name="Active Interaction", default=0)
    preview_image: StringProperty(name="Preview", description="Name of the preview image of the color's exemplar")
    fidelity_image: StringProperty(
        name="Fidelity Plot",
        description="Name of the image plotting the example's pair-correlation functions (and slope histograms) "
        "beside those of the color painted into the example's region",
    )
    fidelity_rdf_l2: FloatProperty(
        name="pcf L2", default=-1.0,
        description="Worst L2 distance between the pcf of the color's self-synthesis and the example's "
        "(negative: not computed)",
    )
    fidelity_density: FloatProperty(
        name="Density Factor", default=1.0,
        description="Density of the color's self-synthesis over the example's (the category farthest from 1)",
    )
    fidelity_axes: FloatVectorProperty(
        name="Plot Axes", size=3,
        description="Ends of the fidelity plot's axes: distance (m), pcf, slope (degrees; 0 without a slope panel)",
    )
    fidelity_note: StringProperty(name="Fidelity Note", description="Why the color has no fidelity view")
    iterations_per_instance: FloatProperty(
        name="Iterations per Instance", default=0.0, min=0.0, soft_max=200.0,
        description="Most proposals the synthesis makes per instance when this color is pasted or brushed (0: the "
        "engine's default, 40); it stops sooner once what it paints matches the example as closely as the example's "
        "own counting noise allows",
    )
    influence_radius: FloatProperty(
        name="Influence", default=-1.0, min=-1.0, unit='LENGTH',
        description="Region of influence of this color: how far around a paste the content conditions it "
        "(negative: the panel's setting)",
    )
    pattern_line: StringProperty(
        name="Pattern", description="How an arrangement color paints (empty: a color of statistics)",
    )
    fidelity_legend: StringProperty(name="Fidelity Legend",
                                    description="Which hue of the plot is which category, with its own pcf L2")
    builtin: BoolProperty(name="Built-in", default=False,
                          description="A color of the built-in palette, learned from an exemplar made by code")

    def fidelity_line(self):
        """The one-line figure of the color's fidelity view, or why it has none."""
        if self.fidelity_rdf_l2 < 0.0:
            return self.fidelity_note or "No fidelity view"
        return fidelity_line(self.fidelity_rdf_l2, self.fidelity_density)

    def fidelity_axes_lines(self):
        """What the fidelity plot's axes span, as the lines the panel writes under it (the plot holds no text)."""
        distance, pcf, slope = self.fidelity_axes
        lines = [f"pcf by distance 0–{distance:.1f} m, 0–{pcf:.1f} (grey: 1, random)"]
        if slope > 0.0:
            lines.append(f"right: share by slope 0–{slope:.0f}°")
        lines.append("solid: example, dashed: painted into its region")
        if self.fidelity_legend:
            lines.append(f"pcf L2 by category: {self.fidelity_legend}")
        return lines


FALLOFFS = (
    ("CONSTANT", "Constant", "The same opacity over the whole brush"),
    ("SMOOTH", "Smooth", "Opacity falls off smoothly to the brush's edge"),
    ("LINEAR", "Linear", "Opacity falls off linearly to the brush's edge"),
)

SIDES = (
    ("EAST", "+X", "Drag the region's +X side"),
    ("WEST", "-X", "Drag the region's -X side"),
    ("NORTH", "+Y", "Drag the region's +Y side"),
    ("SOUTH", "-Y", "Drag the region's -Y side"),
)


class WORLDPAINT_PG_stroke_point(bpy.types.PropertyGroup):
    """One point of a brush stroke, as Blender's own paint operators record them."""

    location: FloatVectorProperty(name="Location", size=3, subtype='XYZ', unit='LENGTH')


class WORLDPAINT_PG_settings(bpy.types.PropertyGroup):
    # no poll callback: a Python callback on a property keeps bpy (Blender as a module) from exiting; the
    # operators check that the terrain is a mesh instead
    terrain: PointerProperty(name="Terrain", type=bpy.types.Object, description="The terrain mesh instances stand on")
    categories: CollectionProperty(type=WORLDPAINT_PG_category)
    active_category_index: IntProperty(name="Active Category", default=0)
    palette: CollectionProperty(type=WORLDPAINT_PG_color)
    active_color_index: IntProperty(name="Active Color", default=0)
    region_mode: EnumProperty(name="Region", items=REGION_MODES, default="SELECTION")
    region_radius: FloatProperty(
        name="Radius", default=20.0, min=0.01, soft_max=1000.0, unit='LENGTH',
        description="Radius of the circle around the 3D cursor",
    )
    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed of the synthesis")
    learn_elevation: BoolProperty(
        name="Height Preference", default=False,
        description="Learn Color also learns which terrain heights the example occupies; heights beyond the "
        "example's range are treated like its highest or lowest ones",
    )
    active_layer: StringProperty(
        name="Active Layer", default="default",
        description="The layer the tools act on when Active Layer Only is on (categories have a layer each)",
    )
    layer_only: BoolProperty(
        name="Active Layer Only", default=False,
        description="The tools change only the categories of the active layer: the other layers' content stays as it "
        "is and conditions the result",
    )
    learn_maps: StringProperty(
        name="Scene Maps",
        description="Maps made in the scene that Learn Color learns too (comma-separated; ticked in the Paint panel)",
    )
    learn_relations: CollectionProperty(type=WORLDPAINT_PG_learn_relation)
    learn_oriented: StringProperty(
        name="Oriented Pairs",
        description="Learn Color also learns how these pairs ('category:other', comma-separated) depend on "
        "direction (an oriented rdf)",
    )
    auto_influence: BoolProperty(
        name="Automatic Influence", default=True,
        description="Region of influence as wide as the color's interaction radius",
    )
    influence_radius: FloatProperty(
        name="Influence", default=10.0, min=0.0, unit='LENGTH',
        description="Width of the band around the region whose content conditions the paste (0 disables it)",
    )
    brush_radius: FloatProperty(
        name="Radius", default=20.0, min=0.1, soft_max=500.0, unit='LENGTH',
        description="Radius of the brush, eraser and pipette on the terrain (F in the viewport)",
    )
    brush_spacing: FloatProperty(
        name="Spacing", default=0.5, min=0.05, max=2.0,
        description="A new dab each time the brush has moved this fraction of its radius",
    )
    brush_opacity: FloatProperty(
        name="Opacity", default=1.0, min=0.01, max=1.0, subtype='FACTOR',
        description="How much of the brush color replaces the color under the brush",
    )
    brush_falloff: EnumProperty(name="Falloff", items=FALLOFFS, default="CONSTANT")
    erase_category: StringProperty(name="Erase", description="Category the eraser removes (empty: all)")
    gradient_end: StringProperty(name="To Color", description="Palette color at the end of the gradient")
    stretch_side: EnumProperty(name="Side", items=SIDES, default="EAST")
    pattern_boundaries: PointerProperty(
        name="Boundaries", type=bpy.types.Collection,
        description="Curves in this collection stop a painted arrangement: no element or edge crosses them",
    )
    pattern_flow: PointerProperty(
        name="Flow", type=bpy.types.Collection,
        description="Curves in this collection orient an arrangement whose rotation follows the flow field",
    )
    pattern_start: EnumProperty(name="Start", items=PATTERN_STARTS, default="CENTER")
    village: PointerProperty(type=WORLDPAINT_PG_village)
    terrain_edit: PointerProperty(type=WORLDPAINT_PG_terrain_edit)
    sketch: PointerProperty(type=WORLDPAINT_PG_sketch)
    place: PointerProperty(type=WORLDPAINT_PG_place)
    world: PointerProperty(type=WORLDPAINT_PG_world)

    def learn_relation(self, category, other):
        """How the interaction matrix says ``category`` relates to ``other``: AUTO, NONE or ORIENTED."""
        for cell in self.learn_relations:
            if (cell.category, cell.other) == (category, other):
                return cell.how
        return "AUTO"

    def learn_pairs(self, how):
        """The matrix's pairs of one kind (NONE or ORIENTED) as Learn Color takes them: 'category:other, ...'."""
        return ", ".join(f"{c.category}:{c.other}" for c in self.learn_relations if c.how == how)


_register_classes, _unregister_classes = bpy.utils.register_classes_factory(
    (WORLDPAINT_PG_category, WORLDPAINT_PG_interaction, WORLDPAINT_PG_learn_relation, WORLDPAINT_PG_color,
     WORLDPAINT_PG_stroke_point, WORLDPAINT_PG_village_event, WORLDPAINT_PG_village, WORLDPAINT_PG_terrain_edit,
     WORLDPAINT_PG_waterfall_controller,
     WORLDPAINT_PG_sketch_point, WORLDPAINT_PG_sketch_stroke, WORLDPAINT_PG_sketch, WORLDPAINT_PG_component,
     WORLDPAINT_PG_texture_edit, WORLDPAINT_PG_texture_atlas, WORLDPAINT_PG_variety, WORLDPAINT_PG_place,
     WORLDPAINT_PG_world, WORLDPAINT_PG_village_site, WORLDPAINT_PG_settings)
)


def register():
    _register_classes()
    bpy.types.Scene.worldpaint = PointerProperty(type=WORLDPAINT_PG_settings)
    bpy.types.Object.worldpaint_waterfall = PointerProperty(type=WORLDPAINT_PG_waterfall_controller)
    bpy.types.Object.worldpaint_variety = PointerProperty(type=WORLDPAINT_PG_variety)
    bpy.types.Object.worldpaint_site = PointerProperty(type=WORLDPAINT_PG_village_site)


def unregister():
    del bpy.types.Object.worldpaint_site
    del bpy.types.Object.worldpaint_variety
    del bpy.types.Object.worldpaint_waterfall
    del bpy.types.Scene.worldpaint
    _unregister_classes()
