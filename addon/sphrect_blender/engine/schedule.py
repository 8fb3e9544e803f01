"""Renderer calls: how a render's samples are split into calls, and cancelling the call in progress.

The renderer checks for cancellation between tiles, so short calls keep Esc responsive; the split is fixed
(not timed) so that renders are reproducible: a script reproduces an engine render by the same calls."""
import threading

# Camera samples (over all pixels) per renderer call. (Far below the renderer's own per-pixel limit,
# sphrect.MAX_SAMPLES_PER_CALL, which a call therefore never reaches.)
MAX_CALL_SAMPLES = 1 << 18

_cancel_requested = threading.Event()
_active = set()                 # renderers inside a render() call
_active_lock = threading.Lock()


def split_samples(total, passes):
    """Samples per progressive pass: `passes` near-equal parts of `total`, none empty."""
    passes = max(1, min(passes, total))
    base, extra = divmod(total, passes)
    return [base + (1 if i < extra else 0) for i in range(passes)]


def sample_schedule(total, passes, pixels):
    """Samples of each renderer call: `passes` display updates, each split into calls of at most
    MAX_CALL_SAMPLES camera samples."""
    cap = max(1, MAX_CALL_SAMPLES // max(1, pixels))
    calls = []
    for n in split_samples(total, passes):
        while n > 0:
            calls.append(min(n, cap))
            n -= calls[-1]
    return calls


def request_cancel():
    """Cancel the running render from a script or another thread (as Esc does in the window); called while none
    runs, the next render is cancelled before it renders anything (as sphrect.Renderer.cancel does), so a request
    just before F12 starts is not lost."""
    _cancel_requested.set()
    with _active_lock:
        for renderer in _active:
            renderer.cancel()


def cancel_requested():
    return _cancel_requested.is_set()


def clear_cancel_request():
    """A render ended: the cancellation that stopped it is used up."""
    _cancel_requested.clear()


def run_call(renderer, samples, progress, time_budget=None):
    """One renderer call, cancellable at once by request_cancel() from any thread. False if cancelled."""
    with _active_lock:
        _active.add(renderer)
    try:
        if _cancel_requested.is_set():
            return False
        return renderer.render(samples, time_budget=time_budget, progress=progress)
    finally:
        with _active_lock:
            _active.discard(renderer)
