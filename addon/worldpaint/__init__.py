"""WorldPaint: learn the statistics of an example arrangement of instances as a color and paste new arrangements.

This module only registers; see ``props`` (scene data), ``ops`` (one operator per concern), ``ui`` (drawing) and
``bridge`` (the only place that converts between bpy and the engine).
"""

from . import ops, props, ui

_modules = (props, ops, ui)


def register():
    for module in _modules:
        module.register()


def unregister():
    for module in reversed(_modules):
        module.unregister()
