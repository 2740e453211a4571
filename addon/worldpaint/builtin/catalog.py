"""The built-in palette: what each color is, the exemplar it is learned from, and the prototype of each category.

A color is learned on demand (``learn``) from its exemplar; the catalog only describes. Categories shared by two
colors (the shrub of the grove and of the scrub, the boulder of the pine slope and of the meadow) are one category
with one prototype.
"""

from typing import NamedTuple

from . import exemplars


class GraphStyle(NamedTuple):
    """How a graph category's synthesized paths are shown: the ribbon's width and how deep its middle sinks."""

    width: float
    depth: float = 0.0


class BuiltinColor(NamedTuple):
    identifier: str
    name: str
    description: str
    exemplar: object  # a function of no argument returning an ``exemplars.Exemplar``
    arrangement: bool = False  # learned as an arrangement (a pattern grown from its reference)


COLORS = (
    BuiltinColor("PINE_SLOPE", "Pine Slope", "Pines 3 m apart or more, denser the steeper the hillside, with "
                 "boulders among them", exemplars.pine_slope),
    BuiltinColor("BROADLEAF_GROVE", "Broadleaf Grove", "Groves of broadleaf trees with shrubs around their edges",
                 exemplars.broadleaf_grove),
    BuiltinColor("MEADOW_BOULDERS", "Meadow with Boulders", "Grass tufts over a meadow, thicker around small "
                 "groups of boulders", exemplars.meadow_with_boulders),
    BuiltinColor("SCRUB", "Scrub", "Junipers, patches of shrubs and scattered stones", exemplars.scrub),
    BuiltinColor("RIVERSIDE_REEDS", "Riverside Reeds", "A stream with brooks, reed beds along their banks and "
                 "willows farther out", exemplars.riverside_reeds),
    BuiltinColor("ORCHARD_ROWS", "Orchard Rows", "Fruit trees planted in rows (a pattern grown from a planted "
                 "block)", exemplars.orchard_rows, arrangement=True),
    BuiltinColor("HAMLET_STREET", "Hamlet Street", "A winding street with side lanes, cottages facing it and "
                 "garden trees behind them", exemplars.hamlet_street),
    BuiltinColor("FARMLAND_HEDGES", "Farmland Hedges", "Farm lanes around fields, lined with hedges and a few "
                 "oaks", exemplars.farmland_hedges),
)

BY_IDENTIFIER = {color.identifier: color for color in COLORS}

# the model of each distribution category (``prototypes.BUILDERS``) and the ribbon of each graph category
PROTOTYPES = {
    "Pine": "pine", "Boulder": "boulder", "Broadleaf": "broadleaf", "Shrub": "shrub", "Grass tuft": "grass_tuft",
    "Juniper": "juniper", "Stone": "stone", "Willow": "willow", "Reed": "reed", "Fruit tree": "fruit_tree",
    "Cottage": "cottage", "Garden tree": "garden_tree", "Field oak": "field_oak", "Hedge bush": "hedge_bush",
}
GRAPHS = {"Stream": GraphStyle(5.0, 0.8), "Street": GraphStyle(5.0), "Field lane": GraphStyle(3.0)}


def enum_items():
    """The colors as an EnumProperty's items, then 'ALL'."""
    items = [(c.identifier, c.name, c.description) for c in COLORS]
    return items + [("ALL", "All", "Every color of the built-in palette")]
