"""Access to the compiled engine module ``worldpaint_engine``."""

from . import WorldPaintError


def engine():
    """The engine module; a clear error when the wheel is missing."""
    try:
        import worldpaint_engine
    except ImportError as exc:  # pragma: no cover - only without the bundled wheel
        raise WorldPaintError(f"The WorldPaint engine is not installed ({exc})") from exc
    return worldpaint_engine


def engine_errors():
    """Exception types the engine raises for bad input or cancellation."""
    eng = engine()
    return (eng.EngineError, eng.Cancelled)
