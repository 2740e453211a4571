"""Scene data of the Terrain panel: which roads are cut into the terrain, and how; the waterfall controllers and how
the terrain adapts to them.

The settings live on ``scene.worldpaint.terrain_edit``, a curve's waterfall role on ``object.worldpaint_waterfall``,
so both are saved in the .blend.
"""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

CONTROLLER_KINDS = (
    ("NONE", "None", "Not a waterfall controller"),
    ("CONTACT", "Contact", "Running water on the terrain, from the curve's first point to its last"),
    ("FREE_FALL", "Free-fall", "Water in the air, from the curve's first point to its last"),
    ("POOL", "Pool", "A closed contour of still water at the mean height of its points"),
)


class WORLDPAINT_PG_waterfall_controller(bpy.types.PropertyGroup):
    """A curve's role in a waterfall scene (thesis 4.1.1: the user chooses contact, free-fall or pool)."""

    kind: EnumProperty(name="Waterfall", items=CONTROLLER_KINDS, default="NONE")
    strength: FloatProperty(
        name="Strength", default=0.0, min=0.0, soft_max=100.0,
        description="Flow of a controller starting at a source, its relative share where it leaves a pool or a "
                    "branch (0: the default)",
    )


class WORLDPAINT_PG_terrain_edit(bpy.types.PropertyGroup):
    """How Embed Roads cuts roads into the terrain, and how Build Waterfall builds a waterfall scene."""

    roads: PointerProperty(
        name="Roads", type=bpy.types.Collection,
        description="Collection of road curves to embed (empty: the selected curves, else the current village's roads)",
    )
    width: FloatProperty(
        name="Carriageway", default=5.0, min=0.5, soft_max=30.0, unit='LENGTH',
        description="Width of the level carriageway",
    )
    bank_width: FloatProperty(
        name="Banks", default=8.0, min=0.0, soft_max=50.0, unit='LENGTH',
        description="Width of the cut and fill banks on each side, beyond which the terrain stays as it was",
    )
    smoothing: FloatProperty(
        name="Smoothing", default=0.0, min=0.0, soft_max=100.0, unit='LENGTH',
        description="How far along the road the terrain's heights are averaged into the carriageway's profile "
                    "(0: twice the carriageway width)",
    )
    use_curve_heights: BoolProperty(
        name="Curve Heights", default=False,
        description="The carriageway follows the heights of the curves' points instead of the smoothed terrain",
    )
    reseat: BoolProperty(
        name="Re-seat", default=True,
        description="Move the village's houses and the painted instances with the ground under them",
    )
    controllers: PointerProperty(
        name="Controllers", type=bpy.types.Collection,
        description="Collection of waterfall controller curves (empty: every curve marked as a controller)",
    )
    waterfall_seed: IntProperty(name="Seed", default=0, min=0, description="Seed of the terrain-adapted subdivision")
    min_slope: FloatProperty(
        name="Minimum Slope", default=0.01, min=0.001, max=0.5, subtype='ANGLE',
        description="Contact water runs downhill at least this steeply; control points are lowered to keep it",
    )
    overhang: FloatProperty(
        name="Overhang", default=2.0, min=0.0, soft_max=10.0, unit='LENGTH',
        description="How far the lip of a free-fall reaches out over its pool (0: no overhang)",
    )
    falloff: FloatProperty(
        name="Falloff", default=40.0, min=1.0, soft_max=200.0, unit='LENGTH',
        description="Beyond this distance from the water the terrain stays as it was",
    )
    max_width: FloatProperty(
        name="Widest Water", default=20.0, min=0.5, soft_max=50.0, unit='LENGTH',
        description="Water surfaces are at most this wide (the section model widens gentle rivers without bound)",
    )
    keep_dry: BoolProperty(
        name="Keep Instances Dry", default=True, description="Remove painted instances that stand in the water",
    )
    rock_color: StringProperty(
        name="Rock Color",
        description="Palette color the river rocks are synthesized from, placed by the rock map of the water "
                    "(empty: the built-in river rocks)",
    )
