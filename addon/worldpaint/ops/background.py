"""Long engine work off Blender's main thread: the engine releases the GIL, so the viewport stays responsive.

``BackgroundOperator`` runs one computation with a progress bar and Esc to cancel; ``QueueWorker`` runs a brush
stroke's points in order as they come; ``LatestWorker`` runs only the newest request of a drag. None of them touches
Blender data off the main thread: the computations take and return plain arrays.
"""

import queue
import threading
import time

from bpy.props import FloatProperty

from ..bridge import WorldPaintError, engine
from .common import report_errors

# how often a live edit in the viewport (a brush stroke, a region following the mouse) shows its newest result
REFRESH_SECONDS = 0.05


def with_progress(context, compute):
    """Runs compute(progress) with Blender's progress indicator when there is a window manager."""
    wm = context.window_manager
    if wm is None:
        return compute(None)

    def progress(fraction, _stage=None):
        wm.progress_update(fraction)
        return True

    wm.progress_begin(0.0, 1.0)
    try:
        return compute(progress)
    finally:
        wm.progress_end()


class BackgroundOperator:
    """An operator whose work is ``_prepare`` (main thread: validate, extract), ``_compute(progress)`` (any thread:
    engine only) and ``_apply(context, result)`` (main thread: change the scene).

    From a script (``execute``) it runs to completion, or until its time limit, which a headless run sets in place
    of Esc. From the UI (``invoke``) the computation runs on a worker thread while a modal handler shows the progress
    (with the stage the engine names, when it has stages) and Esc cancels; the scene only changes once the result is
    complete, so a cancelled operation changes nothing.
    """

    progress_text = "Working"
    # a search that keeps its best result so far when stopped (Learn Village) applies it after Esc too
    keeps_best_on_cancel = False

    time_limit: FloatProperty(name="Time Limit", default=0.0, min=0.0, unit='TIME_ABSOLUTE', options={'SKIP_SAVE'},
                              description="Stop after this many seconds, changing nothing (0: no limit); for scripts "
                                          "and headless runs, where there is no Esc")

    def execute(self, context):
        def run():
            self._prepare(context)
            result = with_progress(context, self._compute_in_time)
            return self._apply(context, result)

        return report_errors(self, run)

    def _compute_in_time(self, progress):
        """``_compute`` told to stop once the time limit has passed; the error then says so."""
        if self.time_limit <= 0.0:
            return self._compute(progress)
        deadline = time.monotonic() + self.time_limit

        def in_time(fraction, stage=None):
            go_on = progress is None or progress(fraction, stage)
            return go_on and time.monotonic() < deadline

        try:
            return self._compute(in_time)
        except engine.engine_error() as exc:
            if engine.is_cancelled(exc) and time.monotonic() >= deadline:
                raise WorldPaintError(f"{self.progress_text}: stopped at the time limit of {self.time_limit:g} s; "
                                      "the scene is unchanged") from None
            raise

    def invoke(self, context, _event):
        def start():
            self._prepare(context)
            self._fraction, self._stage = 0.0, None
            self._cancel = False
            self._outcome = None
            self._worker = threading.Thread(target=self._work, daemon=True)
            self._worker.start()
            wm = context.window_manager
            self._timer = wm.event_timer_add(0.1, window=context.window)
            wm.progress_begin(0.0, 1.0)
            wm.modal_handler_add(self)
            return {'RUNNING_MODAL'}

        return report_errors(self, start)

    def _work(self):
        def progress(fraction, stage=None):
            self._fraction, self._stage = fraction, stage
            return not self._cancel

        try:
            self._outcome = ("ok", self._compute_in_time(progress))
        except Exception as exc:  # noqa: BLE001 - handed to the main thread, which reports it
            self._outcome = ("error", exc)

    def modal(self, context, event):
        if event.type == 'ESC':
            self._cancel = True
        if event.type != 'TIMER':
            return {'RUNNING_MODAL'}
        context.window_manager.progress_update(self._fraction)
        if context.area is not None:
            doing = f"{self.progress_text}, {self._stage}" if self._stage else self.progress_text
            context.area.header_text_set(f"{doing}: {self._fraction:.0%} (Esc to cancel)")
        if self._worker.is_alive():
            return {'RUNNING_MODAL'}
        self._end(context)
        kept = self.keeps_best_on_cancel and self._outcome is not None and self._outcome[0] == "ok"
        if self._cancel and not kept:
            self.report({'INFO'}, f"{self.progress_text}: cancelled, nothing changed")
            return {'CANCELLED'}
        kind, value = self._outcome or ("error", RuntimeError("the computation stopped without a result"))

        def raise_error():
            raise value

        if kind == "error":
            return report_errors(self, raise_error)
        return report_errors(self, lambda: self._apply(context, value))

    def cancel(self, context):
        self._cancel = True
        self._worker.join()
        self._end(context)

    def _end(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        if context.area is not None:
            context.area.header_text_set(None)


class QueueWorker:
    """Feeds items to ``handle`` on a thread, in order; ``close`` waits for the queue to drain, ``abort`` drops it."""

    def __init__(self, handle):
        self._handle = handle
        self._queue = queue.Queue()
        self._aborted = False
        self.error = None
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def put(self, item):
        self._queue.put(item)

    def _run(self):
        while True:
            item = self._queue.get()
            if item is None:
                return
            if self.error is None and not self._aborted:
                try:
                    self._handle(item)
                except Exception as exc:  # noqa: BLE001 - read by the main thread
                    self.error = exc

    def close(self):
        self._queue.put(None)
        self._thread.join()

    def abort(self):
        self._aborted = True
        self.close()


class LatestWorker:
    """Computes ``compute(request)`` on a thread for the newest request only; ``take`` returns the newest result."""

    def __init__(self, compute):
        self._compute = compute
        self._lock = threading.Lock()
        self._wake = threading.Event()
        self._request = None
        self._result = None
        self._closed = False
        self.busy = False
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def request(self, value):
        with self._lock:
            self._request = value
        self._wake.set()

    def take(self):
        """(request, result or exception) of the newest finished computation, once; None when there is none."""
        with self._lock:
            out, self._result = self._result, None
        return out

    def _run(self):
        while True:
            self._wake.wait()
            with self._lock:
                self._wake.clear()
                value, self._request = self._request, None
                if self._closed:
                    return
                self.busy = value is not None
            if value is None:
                continue
            try:
                result = self._compute(value)
            except Exception as exc:  # noqa: BLE001 - read by the main thread
                result = exc
            with self._lock:
                self._result = (value, result)
                self.busy = self._request is not None

    def idle(self):
        with self._lock:
            return not self.busy and self._request is None

    def close(self):
        with self._lock:
            self._closed = True
        self._wake.set()
        self._thread.join()
