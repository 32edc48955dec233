"""The package's type stubs (``__init__.pyi``), written from the engine's
job descriptions (issue #36): every job's function with the engine's fields,
types, choices and defaults, and the package's other functions as they are.

    python -m asperity._stubs > python/asperity/__init__.pyi

(with the package and its built module importable); the test suite checks
that the committed stubs are current.
"""

from __future__ import annotations

import inspect

import asperity
from asperity._jobs import annotation, describe

HEADER = '''"""Type stubs of the asperity package, written by ``python -m asperity._stubs``
from the engine's job descriptions: do not edit by hand."""

from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Literal, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from .api import Result as Result
from .errors import MemoryLimitError as MemoryLimitError, TimeLimitError as TimeLimitError
from .sweep import sweep as sweep
from .types import HeightField as HeightField, Mesh as Mesh, PointSet as PointSet

Surface = Union[Mesh, HeightField, PointSet]

__version__: str
__all__: List[str]
'''


def _default(value) -> str:
    return "..." if value is inspect.Parameter.empty else repr(value)


def _job_stub(name: str, f) -> str:
    desc = describe(f.job)
    fields = {d["name"]: d for d in desc["fields"]}
    parts, keyword_only = [], False
    for p in inspect.signature(f).parameters.values():
        if p.kind is p.VAR_KEYWORD:
            parts.append("**params: Any")
            continue
        if p.kind is p.KEYWORD_ONLY and not keyword_only:
            parts.append("*")
            keyword_only = True
        if p.name in fields:
            t = annotation(fields[p.name])
        elif p.name == "seed":
            t = "int"
        elif p.name == "threads":
            t = "Optional[int]"
        else:
            t = "Any"
        d = "" if p.default is p.empty else f" = {_default(p.default)}"
        parts.append(f"{p.name}: {t}{d}")
    return f"def {name}({', '.join(parts)}) -> {f.result}: ..."


def _plain_stub(name: str, f) -> str:
    sig = inspect.signature(f)
    parts, keyword_only = [], False
    for p in sig.parameters.values():
        t = "" if p.annotation is p.empty else f": {p.annotation}"
        if p.kind is p.VAR_KEYWORD:
            parts.append(f"**{p.name}{t or ': Any'}")
            continue
        if p.kind is p.KEYWORD_ONLY and not keyword_only:
            parts.append("*")
            keyword_only = True
        d = "" if p.default is p.empty else f" = {_default(p.default)}"
        parts.append(f"{p.name}{t}{d}")
    ret = "Any" if sig.return_annotation is sig.empty else sig.return_annotation
    return f"def {name}({', '.join(parts)}) -> {ret}: ..."


def stub_text() -> str:
    """The stubs as text."""
    lines = [HEADER]
    for name in sorted(asperity.__all__):
        f = getattr(asperity, name)
        if name == "sweep" or not inspect.isfunction(f):
            continue
        lines.append(_job_stub(name, f) if hasattr(f, "job") else _plain_stub(name, f))
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(stub_text(), end="")
