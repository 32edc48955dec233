"""Finding asperity's Python package, and running its jobs from Blender.

The add-on holds no algorithm: every surface comes from the ``asperity``
package (the same Rust engine as the CLI). It is looked for, in order, in the
copy the add-on's zip carries (``vendor/``, put there by ``blender/build.py``),
in the folder set in the add-on's preferences, and on Blender's ``sys.path``.

A job runs on a worker thread (the engine releases the GIL), reporting
``(done, total, message)``; setting the cancel event makes the next report
raise, which stops the engine's job (it checks between steps) and leaves
nothing built.
"""
from __future__ import annotations

import importlib
import os
import sys
import threading
from pathlib import Path

_VENDOR = Path(__file__).with_name("vendor")


class Cancelled(Exception):
    """The user pressed Esc."""


def package(folder: str = ""):
    """The ``asperity`` module, or raise ImportError saying where it was looked for."""
    tried = []
    for candidate in (_VENDOR, Path(folder) if folder else None,
                      Path(os.environ["ASPERITY_PYTHONPATH"]) if os.environ.get("ASPERITY_PYTHONPATH") else None):
        if candidate is not None and (candidate / "asperity" / "__init__.py").exists():
            if str(candidate) not in sys.path:
                sys.path.insert(0, str(candidate))
            break
        if candidate is not None:
            tried.append(str(candidate))
    try:
        return importlib.import_module("asperity")
    except ImportError as e:
        raise ImportError(
            "asperity's Python package was not found (looked in "
            f"{', '.join(tried) or 'the add-on'} and on sys.path): install the add-on zip that "
            "blender/build.py makes, or set its folder in Edit > Preferences > Add-ons > asperity"
        ) from e


class Job:
    """``fn(progress=callback)`` on a worker thread.

    ``progress`` is ``(done, total, message)``, ``result`` the return value and
    ``error`` the exception (``Cancelled`` after :meth:`cancel`).
    """

    def __init__(self, fn):
        self.progress = (0, 0, "")
        self.result = None
        self.error = None
        self._cancel = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(fn,), name="asperity-blender", daemon=True)

    def _report(self, done, total, message):
        self.progress = (done, total, message)
        if self._cancel.is_set():
            raise Cancelled()

    def _run(self, fn):
        try:
            self.result = fn(progress=self._report)
        except BaseException as e:  # noqa: BLE001 - handed to the operator
            self.error = Cancelled() if self._cancel.is_set() else e

    def start(self):
        self._thread.start()
        return self

    def cancel(self):
        self._cancel.set()

    def done(self) -> bool:
        return not self._thread.is_alive()

    def wait(self):
        """Blocks until the job ends; returns its result or raises its error."""
        self._thread.join()
        if self.error is not None:
            raise self.error
        return self.result
