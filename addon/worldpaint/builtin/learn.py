"""Learning a built-in color from its exemplar through the engine: deterministic, and fast enough to run when an
artist appends the color (nothing learned is shipped, so a newer engine learns the colors its own way)."""

from typing import NamedTuple

from ..bridge import engine

MAPS = ("slope",)  # what Learn Color learns by default: the slopes the example stands on


class Learned(NamedTuple):
    """A learned built-in color: its JSON and the terrain its exemplar stands on (for its fidelity view)."""

    color_json: str
    terrain: object
    counts: dict  # {category: instances (paths of a graph)} of the exemplar


def learn(color, name):
    """The ``catalog.BuiltinColor`` ``color`` learned from its exemplar under the palette name ``name``."""
    exemplar = color.exemplar()
    scene = exemplar.engine_scene()
    if color.arrangement:
        color_json = engine.learn_arrangement(scene, exemplar.region, name)
    else:
        color_json = engine.learn_color(scene, exemplar.region, name, MAPS)
    return Learned(color_json, exemplar.terrain, exemplar.counts())
