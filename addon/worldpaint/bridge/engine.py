"""Access to the compiled engine module ``worldpaint_engine``."""

from . import WorldPaintError


def engine():
    """The engine module; a clear error when the wheel is missing."""
    try:
        import worldpaint_engine
    except ImportError as exc:  # pragma: no cover - only without the bundled wheel
        raise WorldPaintError(f"The WorldPaint engine is not installed ({exc})") from exc
    return worldpaint_engine


def engine_error():
    """The base class of every exception the engine raises (``Cancelled``, ``InputError`` and the rest)."""
    return engine().WorldPaintError


def is_cancelled(exc):
    return isinstance(exc, engine().Cancelled)
