"""Scene data of the Place panel: how a real place is imported (File › Import › WorldPaint Place).

It lives on ``scene.worldpaint.place`` so it is saved in the .blend with the scene. Where the imported place is (its
origin, projection and sources) is kept on the place's collection instead (see ``bridge.place``).
"""

import bpy
from bpy.props import FloatProperty, IntProperty


class WORLDPAINT_PG_place(bpy.types.PropertyGroup):
    cell: FloatProperty(
        name="Terrain Cell", default=0.0, min=0.0, soft_max=200.0, unit='LENGTH',
        description="Spacing of the terrain mesh's vertices (0: the elevation model's own spacing)",
    )
    margin: FloatProperty(
        name="Margin", default=200.0, min=0.0, soft_max=5000.0, unit='LENGTH',
        description="How far the terrain reaches beyond the map layers and the inventory",
    )
    tree_species: IntProperty(
        name="Tree Species", default=12, min=1, max=64,
        description="The most common species of an inventory each become a category; the rarer ones are one "
        "category, 'Other trees'",
    )
