"""Scene data of the Terrain panel: which roads are cut into the terrain, and how.

It lives on ``scene.worldpaint.terrain_edit`` so it is saved in the .blend with the scene.
"""

import bpy
from bpy.props import BoolProperty, FloatProperty, PointerProperty


class WORLDPAINT_PG_terrain_edit(bpy.types.PropertyGroup):
    """How Embed Roads cuts roads into the terrain."""

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
