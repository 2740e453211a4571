"""Materials that show each painted instance's tint (its colour noise).

The tint of a point (the point attribute ``tint``, see ``points``) reaches its instance through Instance on Points;
a material reads it with an Attribute node of type Instancer, which falls back to the object's own custom property
``tint`` (what Convert to Objects writes). The shader group "WorldPaint Tint" turns a colour by it: brightness times
1 + tint and a hue shift of HUE_SHIFT × tint. Tinting a material puts that group in front of the Base Color of each
of its Principled BSDF nodes, once.
"""

import bpy

from . import compat
from .instances import TINT_ATTRIBUTE

GROUP_NAME = "WorldPaint Tint"
HUE_SHIFT = 0.05  # of a full turn of hue per unit of tint


def tint_group():
    """The shader group "WorldPaint Tint" (Color in, Color out), built once per file."""
    group = bpy.data.node_groups.get(GROUP_NAME)
    if group is not None and group.bl_idname == 'ShaderNodeTree':
        return group
    group = bpy.data.node_groups.new(GROUP_NAME, 'ShaderNodeTree')
    group.interface.new_socket("Color", in_out='INPUT', socket_type='NodeSocketColor')
    group.interface.new_socket("Color", in_out='OUTPUT', socket_type='NodeSocketColor')
    nodes, links = group.nodes, group.links
    group_in = nodes.new('NodeGroupInput')
    group_in.location = (-600, 0)
    group_out = nodes.new('NodeGroupOutput')
    group_out.location = (300, 0)
    attribute = nodes.new('ShaderNodeAttribute')
    attribute.attribute_type = 'INSTANCER'
    attribute.attribute_name = TINT_ATTRIBUTE
    attribute.location = (-600, -200)
    value = nodes.new('ShaderNodeMath')
    value.operation = 'ADD'
    value.inputs[1].default_value = 1.0
    value.location = (-350, -150)
    hue = nodes.new('ShaderNodeMath')
    hue.operation = 'MULTIPLY_ADD'
    hue.inputs[1].default_value = HUE_SHIFT
    hue.inputs[2].default_value = 0.5
    hue.location = (-350, -350)
    shift = nodes.new('ShaderNodeHueSaturation')
    shift.location = (0, 0)
    links.new(attribute.outputs["Fac"], value.inputs[0])
    links.new(attribute.outputs["Fac"], hue.inputs[0])
    links.new(value.outputs["Value"], shift.inputs["Value"])
    links.new(hue.outputs["Value"], shift.inputs["Hue"])
    links.new(group_in.outputs["Color"], shift.inputs["Color"])
    links.new(shift.outputs["Color"], group_out.inputs["Color"])
    return group


def tint_material(material):
    """Puts the tint group in front of the Base Color of each Principled BSDF of ``material`` (made to use nodes);
    returns how many it changed (0 when it has none, or each already has the group)."""
    tree, group, changed = compat.uses_nodes(material), tint_group(), 0
    for node in list(tree.nodes):
        if node.bl_idname != 'ShaderNodeBsdfPrincipled':
            continue
        base = node.inputs["Base Color"]
        feeding = base.links[0].from_socket if base.is_linked else None
        if feeding is not None and getattr(feeding.node, "node_tree", None) is group:
            continue
        tinted = tree.nodes.new('ShaderNodeGroup')
        tinted.node_tree = group
        tinted.location = (node.location.x - 200, node.location.y - 100)
        if feeding is None:
            tinted.inputs["Color"].default_value = base.default_value
        else:
            tree.links.new(feeding, tinted.inputs["Color"])
        tree.links.new(tinted.outputs["Color"], base)
        changed += 1
    return changed


def tint_collection(collection):
    """Tints the materials of every mesh in ``collection`` and its children; returns (materials changed, meshes
    without any material)."""
    seen, changed, bare = set(), 0, 0
    for obj in collection.all_objects:
        if obj.type != 'MESH':
            continue
        materials = [slot.material for slot in obj.material_slots if slot.material is not None]
        bare += not materials
        for material in materials:
            if material.name not in seen:
                seen.add(material.name)
                changed += tint_material(material) > 0
    return changed, bare
