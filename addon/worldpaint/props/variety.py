"""Model variety settings of a mesh object (``object.worldpaint_variety``): how it is cut into components, the
collections of its parts and of its generated variants, its texture edits and atlases, and what the last generation
made."""

import bpy
from bpy.props import CollectionProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

LABEL_SOURCES = (
    ("FACE_SETS", "Face Sets", "One component per face set (Sculpt Mode > Face Sets)"),
    ("MATERIALS", "Materials", "One component per material slot"),
    ("SEAMS", "Seams", "The edges marked as seams cut the mesh into components (no vertex is added)"),
    ("ATTRIBUTE", "Attribute", "One component per value of an integer face attribute"),
)


class WORLDPAINT_PG_component(bpy.types.PropertyGroup):
    """One component of a decomposed model: its label, its size and its connecting regions."""

    label: IntProperty(name="Label")
    faces: IntProperty(name="Faces")
    regions: StringProperty(name="Regions", description="The components it is joined to")
    repeat: IntProperty(name="Repeat", default=0, min=0, max=64,
                        description="Repeat the component up to this many times in a row (a local cycle: its two "
                        "connecting regions must be alike; 0: once)")
    pick: PointerProperty(name="Pick", type=bpy.types.Object, poll=lambda _self, obj: obj.type == 'MESH',
                          description="The copy of the part that Generate Variants By Hand assembles (empty: the "
                          "original piece)")


class WORLDPAINT_PG_texture_edit(bpy.types.PropertyGroup):
    """One texture edit: a copy of the base texture with details painted in (a texture component, seed §5)."""

    image: PointerProperty(name="Image", type=bpy.types.Image,
                           description="A copy of the base texture with details painted in")


class WORLDPAINT_PG_texture_atlas(bpy.types.PropertyGroup):
    """One texture component atlas made by the last generation: the base texture with its components painted in."""

    image: PointerProperty(name="Image", type=bpy.types.Image)
    edits: StringProperty(name="Edits", description="The texture edits painted into this atlas")


class WORLDPAINT_PG_variety(bpy.types.PropertyGroup):
    source: EnumProperty(name="Components", items=LABEL_SOURCES, default="FACE_SETS",
                         description="What cuts the model into components")
    attribute: StringProperty(name="Attribute", description="Integer face attribute labelling the components")
    root: IntProperty(name="Root", default=-1, min=-1,
                      description="Label of the component that stays in place; -1: the largest")
    parts: PointerProperty(name="Parts", type=bpy.types.Collection,
                           description="One collection per component: its original piece and the edited copies")
    generated: PointerProperty(name="Variants", type=bpy.types.Collection,
                               description="The generated variants: use it as a category's prototypes")
    components: CollectionProperty(type=WORLDPAINT_PG_component)
    active_component: IntProperty(name="Active Component", default=0)
    graph: StringProperty(name="Graph", description="The component graph in one line")
    total: StringProperty(name="Count", description="How many different models the parts can make (#V)")
    count: IntProperty(name="Generate", default=50, min=1, soft_max=1000, description="Variants to generate")
    seed: IntProperty(name="Seed", default=0, min=0)
    report: StringProperty(name="Report", description="What the last generation made")
    base_image: PointerProperty(name="Base Texture", type=bpy.types.Image,
                                description="The texture the edits are painted over (empty: the first image texture "
                                "of the object's materials)")
    texture_edits: CollectionProperty(type=WORLDPAINT_PG_texture_edit)
    active_texture_edit: IntProperty(name="Active Texture Edit", default=0)
    texture_probability: FloatProperty(name="Probability", default=0.5, min=0.0, max=1.0, subtype='FACTOR',
                                       description="How likely a variant is to show each texture edit (one whose "
                                       "faces already show another is skipped)")
    atlases: CollectionProperty(type=WORLDPAINT_PG_texture_atlas)
    texture_report: StringProperty(name="Texture Report", description="What the last generation made of the edits")


classes = (WORLDPAINT_PG_component, WORLDPAINT_PG_texture_edit, WORLDPAINT_PG_texture_atlas, WORLDPAINT_PG_variety)
