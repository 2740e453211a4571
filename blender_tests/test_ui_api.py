"""The panels, lists and tools use only what this Blender's UI API has: every layout call with its keywords, every
icon and every operator they name. Drawing needs a window, which Blender as a Python module has not; this reads the
add-on's drawing code and checks it against the running Blender's own RNA, so a renamed icon or a removed layout
keyword in a new release fails here instead of in an artist's sidebar."""

import ast
import os
import pathlib

import bpy

ADDON = pathlib.Path(__file__).resolve().parents[1] / "addon" / "worldpaint"
LAYOUT_NAMES = {"layout", "row", "col", "column", "box", "sub", "split", "header", "body"}
LAYOUT_FUNCTIONS = bpy.types.UILayout.bl_rna.functions
ICONS = set(LAYOUT_FUNCTIONS["label"].parameters["icon"].enum_items.keys())


def drawing_code():
    for path in sorted([*(ADDON / "ui").glob("*.py"), *(ADDON / "ops").glob("*.py")]):
        yield path.relative_to(ADDON), ast.parse(path.read_text())


def layout_calls():
    """(file, line, method, call) for every call on a UI layout."""
    for name, tree in drawing_code():
        for node in ast.walk(tree):
            if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
                continue
            owner = node.func.value
            is_layout = (isinstance(owner, ast.Name) and owner.id in LAYOUT_NAMES
                         or isinstance(owner, ast.Attribute) and owner.attr == "layout")
            if is_layout:
                yield name, node.lineno, node.func.attr, node


def test_every_layout_call_exists_with_its_keywords():
    calls = list(layout_calls())
    assert len(calls) > 100, "the panels were not found"
    wrong = []
    for name, line, method, call in calls:
        function = LAYOUT_FUNCTIONS.get(method)
        if function is None:
            wrong.append(f"{name}:{line} UILayout.{method} does not exist")
            continue
        known = set(function.parameters.keys())
        wrong += [f"{name}:{line} UILayout.{method} has no keyword '{k.arg}'" for k in call.keywords
                  if k.arg is not None and k.arg not in known]
    assert not wrong, "\n".join(wrong)


def test_every_icon_named_exists():
    named = []
    for name, tree in drawing_code():
        for node in ast.walk(tree):
            if isinstance(node, ast.keyword) and node.arg == "icon":
                named += [(name, c.lineno, c.value) for c in ast.walk(node.value)
                          if isinstance(c, ast.Constant) and isinstance(c.value, str)]
    assert len(named) > 20
    missing = [f"{name}:{line} icon '{icon}'" for name, line, icon in named if icon not in ICONS]
    assert not missing, "\n".join(missing)


def test_every_operator_a_panel_names_is_registered():
    idnames = set()
    for _name, tree in drawing_code():
        for node in ast.walk(tree):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "operator"
                    and node.args and isinstance(node.args[0], ast.Constant)):
                idnames.add(node.args[0].value)
    assert len(idnames) > 15
    missing = [i for i in sorted(idnames)
               if not hasattr(bpy.types, i.split(".")[0].upper() + "_OT_" + i.split(".")[1])]
    assert not missing, missing


def test_the_tools_icons_are_in_this_blender():
    from worldpaint.ui import tools

    icons = bpy.utils.system_resource('DATAFILES', path="icons")
    for tool in tools.TOOLS:
        assert os.path.exists(os.path.join(icons, tool.bl_icon + ".dat")), f"{tool.bl_idname}: {tool.bl_icon}"
