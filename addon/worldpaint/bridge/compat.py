"""The one place that knows how Blender's Python API differs between the versions the add-on supports (4.5 LTS to
the newest 5.x). Each difference is detected by the API it concerns, not by a version number, so a later release
that keeps an API keeps working.

Differences handled here:

- Geometry Nodes modifier inputs: 4.5 stores them as ID properties (``modifier[identifier]``); 5.x has no ID
  properties on the modifier and exposes them as ``modifier.properties.inputs.<identifier>.value``.
  Drawing one in a panel follows the same split.
- Node modes that became menu inputs: Resample Curve's and Set Curve Normal's ``mode`` property is, in 5.x, a
  ``Mode`` menu socket whose items are named by their labels ("Length", "Z Up").
- ``Material.use_nodes``: materials always use nodes in 5.x and setting it is deprecated (removed in 6.0).
"""

import warnings

import bpy

# --- Geometry Nodes modifier inputs -------------------------------------------------------------------------------

def _input_identifier(modifier, name):
    items = modifier.node_group.interface.items_tree if modifier.node_group is not None else {}
    item = items.get(name)
    if item is None or getattr(item, "in_out", 'INPUT') != 'INPUT':
        raise KeyError(f"the node group of modifier '{modifier.name}' has no input '{name}'")
    return item.identifier


def set_modifier_input(modifier, name, value):
    """Sets the Geometry Nodes modifier's input called ``name`` (the node group's interface name)."""
    identifier = _input_identifier(modifier, name)
    properties = getattr(modifier, "properties", None)
    if properties is not None and hasattr(properties, "inputs"):
        getattr(properties.inputs, identifier).value = value
    else:
        modifier[identifier] = value


def modifier_input(modifier, name, default=None):
    """The value of the Geometry Nodes modifier's input called ``name``, or ``default`` when it has none."""
    try:
        identifier = _input_identifier(modifier, name)
    except KeyError:
        return default
    properties = getattr(modifier, "properties", None)
    if properties is not None and hasattr(properties, "inputs"):
        socket = getattr(properties.inputs, identifier, None)
        return default if socket is None else socket.value
    return modifier.get(identifier, default)


def draw_modifier_input(layout, modifier, name, text=None):
    """Draws the Geometry Nodes modifier's input called ``name`` as a field of ``layout``."""
    identifier = _input_identifier(modifier, name)
    properties = getattr(modifier, "properties", None)
    if properties is not None and hasattr(properties, "inputs"):
        layout.prop(getattr(properties.inputs, identifier), "value", text=text or name)
    else:
        layout.prop(modifier, f'["{identifier}"]', text=text or name)


# --- nodes --------------------------------------------------------------------------------------------------------

def set_node_mode(node, identifier, label):
    """Sets a node's ``mode``: the enum property ``identifier`` where the node has one (4.5), else the item
    ``label`` of its "Mode" menu input (5.x)."""
    if hasattr(node, "mode"):
        node.mode = identifier
    else:
        node.inputs["Mode"].default_value = label


# --- materials ----------------------------------------------------------------------------------------------------

def node_material(name):
    """A new material whose shading is a node tree with a Principled BSDF."""
    material = bpy.data.materials.new(name)
    if material.node_tree is None:  # 4.5: a new material has no node tree until it uses nodes
        material.use_nodes = True
    return material


def uses_nodes(material):
    """Makes ``material`` shade with its node tree (4.5: one without nodes renders its diffuse colour, which becomes
    the Principled BSDF's Base Color); returns the node tree."""
    with warnings.catch_warnings():  # 5.x: deprecated and always True; 6.0: gone
        warnings.simplefilter("ignore", DeprecationWarning)
        flat = not getattr(material, "use_nodes", True)
    if material.node_tree is None or flat:
        material.use_nodes = True
        for node in material.node_tree.nodes:
            if node.bl_idname == 'ShaderNodeBsdfPrincipled':
                node.inputs["Base Color"].default_value = material.diffuse_color
    return material.node_tree
