"""The worldpaint engine: learn the statistics of an arrangement of instances and paste new ones.

The engine itself is the compiled module ``_engine``, whose classes and functions this package re-exports;
``worldpaint_engine.world`` fills worlds of any size tile by tile (``python -m worldpaint_engine.world --help``).
"""

from . import _engine
from ._engine import *  # noqa: F403 (the engine's whole surface, as the compiled module names it)
from ._engine import PALETTE_FORMAT_VERSION, __version__  # noqa: F401 (dunder names are not star-imported)

__all__ = [name for name in dir(_engine) if not name.startswith("_")] + ["__version__"]
