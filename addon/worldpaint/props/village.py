"""Scene data of the Village panel: what a village grows on, from and into, and its growth scenario.

It lives on ``scene.worldpaint.village`` so it is saved in the .blend with the scene.
"""

import bpy
from bpy.props import (
    BoolProperty,
    CollectionProperty,
    EnumProperty,
    FloatProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

EVENT_KINDS = (
    ("VILLAGE_TYPE", "Change Village Type", "From here on the village grows as this village type"),
    ("GENERATE", "Generate Buildings", "Seed this many buildings of this type, each connected to the roads"),
)

CONNECTION_MODES = (
    ("AUTO", "Automatic", "Where the existing roads cross the region's border, else the lowest point of the border"),
    ("EMPTIES", "Empties", "The locations of the objects (empties) of the Connections collection"),
    ("ROAD_ENDS", "Road Ends", "The ends of the existing roads that lie inside the region"),
)

CRITERIA = (
    ("INTEREST", "Interest", "The combined interest of the building type, in [0, 1]"),
    ("sociability", "Sociability", "Near enough to the other buildings, not too near, in [-1, 1]"),
    ("worship", "Worship", "Distance to the religious buildings, in [-1, 1]"),
    ("accessibility", "Accessibility", "Distance to the roads, in [-1, 1]"),
    ("slope", "Slope", "How flat the ground is, in [-1, 1]"),
    ("water", "Water", "Distance to water, in [-1, 1]"),
    ("fortification", "Fortification", "Distance to the walls and fortresses, in [-1, 1]"),
    ("domination", "Domination", "How much higher than the surroundings, in [-1, 1]"),
)


class WORLDPAINT_PG_village_event(bpy.types.PropertyGroup):
    """One event of a growth scenario: change the village type, or generate a number of buildings of a type."""

    kind: EnumProperty(name="Event", items=EVENT_KINDS, default="GENERATE")
    village_type: StringProperty(name="Village Type", default="farming",
                                 description="Village type of the encyclopedia the village grows as from here on")
    building: StringProperty(name="Building", default="house", description="Building type of the encyclopedia")
    count: IntProperty(name="Count", default=1, min=1, soft_max=100, description="How many buildings to seed")


class WORLDPAINT_PG_village(bpy.types.PropertyGroup):
    # no poll or update callbacks: a Python callback on a property keeps bpy (Blender as a module) from exiting;
    # the operators check the objects' types instead
    region: PointerProperty(
        name="Region", type=bpy.types.Object,
        description="Closed curve bounding the village (empty: the whole terrain)",
    )
    connection_mode: EnumProperty(name="Connections", items=CONNECTION_MODES, default="AUTO")
    connections: PointerProperty(
        name="Connection Points", type=bpy.types.Collection,
        description="Collection of empties where the village connects to the outside world",
    )
    roads: PointerProperty(
        name="Existing Roads", type=bpy.types.Collection,
        description="Collection of road curves already there: kept as they are, the new roads join them",
    )
    use_water_level: BoolProperty(
        name="Water Level", default=False, description="Everything below a height is water (a sea or a lake)"
    )
    water_level: FloatProperty(name="Level", default=0.0, unit='LENGTH', description="Height of the water")
    water: PointerProperty(
        name="Water", type=bpy.types.Collection,
        description="Collection of curves: closed ones are lakes, open ones rivers",
    )
    river_half_width: FloatProperty(
        name="River Half Width", default=4.0, min=0.0, soft_max=50.0, unit='LENGTH',
        description="Half the width of the rivers drawn as open curves",
    )
    walls: PointerProperty(
        name="Walls", type=bpy.types.Collection, description="Collection of closed curves: fortification walls"
    )
    events: CollectionProperty(type=WORLDPAINT_PG_village_event)
    active_event_index: IntProperty(name="Active Event", default=0)
    # a "//" path is the saved .blend file's folder (see ``bridge.files``)
    encyclopedia_path: StringProperty(
        name="Encyclopedia", subtype='FILE_PATH', options={'ANIMATABLE', 'PATH_SUPPORTS_BLEND_RELATIVE'},
        description="Building encyclopedia JSON file (empty: the one shipped with WorldPaint)",
    )
    encyclopedia_text: PointerProperty(
        name="Encyclopedia Text", type=bpy.types.Text,
        description="Building encyclopedia kept in the .blend, used when no file is given (Learn Village adds the "
        "village types it learns here)",
    )
    learn_name: StringProperty(
        name="Name", default="", description="Name of the learned village type (empty: \"like\" and the region's name)"
    )
    learn_base_type: StringProperty(
        name="Start From", default="",
        description="Village type of the encyclopedia the search starts from (empty: the one whose villages come "
        "nearest the real village)",
    )
    learn_minutes: FloatProperty(
        name="Minutes", default=9.0, min=0.1, soft_max=30.0,
        description="Longest time the search may take (Esc stops it earlier and keeps the best type so far)",
    )
    learn_report: StringProperty(name="Learn Report", description="How the last Learn Village went")
    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed of the village")
    cell: FloatProperty(
        name="Grid Cell", default=2.0, min=0.25, soft_max=10.0, unit='LENGTH',
        description="Grid cell of the interests and roads: finer is more precise and slower",
    )
    parcel_cell: FloatProperty(
        name="Parcel Cell", default=1.0, min=0.25, soft_max=5.0, unit='LENGTH',
        description="Grid cell of the land parcels",
    )
    parcels_as_curves: BoolProperty(
        name="Parcels as Curves", default=False, description="Also draw the land parcels as closed outline curves"
    )
    collection: PointerProperty(
        name="Village", type=bpy.types.Collection,
        description="Collection of the current village: Generate Village replaces what it made there before "
        "(clear this field to keep the village and start a new one)",
    )
    report: StringProperty(name="Report", description="What the last generation made")
    interest_village_type: StringProperty(name="Village Type", default="farming")
    interest_building: StringProperty(name="Building", default="house")
    interest_criterion: EnumProperty(name="Criterion", items=CRITERIA, default="INTEREST")

