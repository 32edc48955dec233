"""Exceptions raised by asperity beyond Python's own.

Bad arguments raise ``ValueError`` or ``TypeError`` with the message the CLI
prints for the same mistake; failing file operations raise ``OSError``.
"""

from __future__ import annotations


class MemoryLimitError(MemoryError):
    """A job would allocate more than the memory budget; nothing was allocated.

    ``needed`` and ``limit`` are the estimate and the budget in bytes. Raise the
    budget with ``asperity.set_limits(max_memory=...)``.
    """

    def __init__(self, message: str, needed: int = 0, limit: int = 0):
        super().__init__(message)
        self.needed = needed
        self.limit = limit


class TimeLimitError(RuntimeError):
    """A job would run longer than the time limit even on a fast machine.

    Raise the limit with ``asperity.set_limits(max_time=...)`` (seconds).
    """
