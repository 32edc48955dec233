"""Progress display for long runs: ``progress=True`` shows a tqdm bar,
a callable receives ``(done, total, message)`` about ten times a second."""

from __future__ import annotations


class _Tqdm:
    def __init__(self):
        from tqdm.auto import tqdm

        self._tqdm = tqdm
        self.bar = None
        self.message = None

    def __call__(self, done: int, total: int, message: str) -> None:
        if total == 0:
            return
        if self.bar is None or message != self.message or total != self.bar.total:
            if self.bar is not None:
                self.bar.close()
            self.bar = self._tqdm(total=total, desc=message or "asperity")
            self.message = message
        self.bar.update(done - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def progress_callback(progress):
    """(callback for the engine, closer)."""
    if progress is True:
        bar = _Tqdm()
        return bar, bar.close
    if progress in (False, None):
        return None, lambda: None
    if callable(progress):
        return progress, lambda: None
    raise TypeError("progress must be True, False or a callable(done, total, message)")


def call(fn, *args, progress=None, **kwargs):
    """Calls the engine function ``fn`` with a progress callback."""
    cb, close = progress_callback(progress)
    try:
        return fn(*args, progress=cb, **kwargs)
    finally:
        close()
