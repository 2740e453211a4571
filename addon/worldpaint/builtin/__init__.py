"""The built-in palette installed with the extension: colors an artist reaches for (a pine slope, a broadleaf grove,
a meadow with boulders, scrub, riverside reeds, orchard rows, a hamlet street, farmland hedges), each learned on
demand from an exemplar built by code, with low-poly prototypes made by code.

``catalog`` says what each color is, ``sampling`` draws the point processes and lines, ``exemplars`` builds each
color's exemplar, ``learn`` learns it through the engine and ``prototypes`` makes the models. The operator that
appends a color to the palette is ``ops.builtin``.
"""
