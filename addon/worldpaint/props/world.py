"""Scene data of the World panel: how a whole world is filled from a map painted on the terrain, and the village
sites placed in it.

The fill's settings live on ``scene.worldpaint.world``; a village site is an empty whose ``worldpaint_site`` says
which village grows there (both saved in the .blend).
"""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from ..bridge import points

MAP_ATTRIBUTE = "WP World Map"


class WORLDPAINT_PG_world(bpy.types.PropertyGroup):
    map_attribute: StringProperty(
        name="Map", default=MAP_ATTRIBUTE,
        description="The terrain's color attribute painted with the World Map swatches (one per palette color); "
        "without it the world is filled with the active color",
    )
    band: FloatProperty(
        name="Transition Band", default=0.0, min=0.0, soft_max=1000.0, unit='LENGTH',
        description="Width over which two neighbouring colors of the map blend (0: three regions of influence)",
    )
    seed: IntProperty(name="Seed", default=0, min=0, description="The same seed fills the same world")
    tile: FloatProperty(
        name="Tile", default=0.0, min=0.0, soft_max=5000.0, unit='LENGTH',
        description="Side of the tiles the world is filled in (0: about 100,000 instances a tile)",
    )
    workers: IntProperty(
        name="Workers", default=0, min=0, max=256,
        description="Worker processes of the local Dask cluster (0: one per core)",
    )
    directory: StringProperty(
        name="Tile Set", default="//world", subtype='DIR_PATH', options={'PATH_SUPPORTS_BLEND_RELATIVE'},
        description="The folder the world's tile set is written to (a tile set there is replaced; a folder of "
        "other files is refused)",
    )
    display: EnumProperty(name="Display", items=points.DISPLAY_MODES, default='PROXY',
                          description="How the viewport shows the loaded instances (a render shows them all)")
    lod_distance: FloatProperty(
        name="LOD Distance", default=300.0, min=0.0, unit='LENGTH',
        description="With the Bounds or Proxy display, instances within this distance of the camera keep their full "
        "mesh",
    )
    cull_distance: FloatProperty(
        name="Cull Distance", default=0.0, min=0.0, unit='LENGTH',
        description="Instances farther than this from the camera are not shown in the viewport (0: all)",
    )
    report: StringProperty(name="Report", description="What the last Fill World made")


class WORLDPAINT_PG_village_site(bpy.types.PropertyGroup):
    """On an empty: a village that Fill World grows at the empty's place before the tiles."""

    is_site: BoolProperty(name="Village Site", default=False)
    village_type: StringProperty(name="Village Type", default="farming",
                                 description="A village type of the scene's encyclopedia")
    buildings: IntProperty(name="Buildings", default=20, min=1, max=2000, description="Buildings the village grows")
    seed: IntProperty(name="Seed", default=0, min=0, description="The village's own seed")
