"""Python functions made from the engine's job parameters (issue #36).

Every engine job has one parameter struct in Rust — documented fields, one
default each, valid ranges, choices — and this module builds a job's Python
function from its description (``_asperity.describe(job)``): the signature
shows the engine's defaults, ``help()`` its documentation, and the keyword
arguments go to the engine as JSON, where the same code that reads the CLI's
flags fills in defaults, refuses unknown names (``TypeError``) and checks
ranges (``ValueError``). No default or choice is written here.

``asperity.dla(**result.params)`` runs a job again: a result's ``params`` (and
a CLI report's) holds the job, the schema version, the seed and every value.
"""

from __future__ import annotations

import functools
import inspect
import json
from pathlib import PurePath
from typing import Any, Callable, Dict, Optional, Sequence, Tuple

import numpy as np

from . import _asperity
from ._run import call

DEFAULT_SEED = _asperity.DEFAULT_SEED

P = inspect.Parameter


@functools.lru_cache(maxsize=None)
def describe(job: str) -> dict:
    """The engine's description of ``job`` (e.g. ``"growth dla"``): its fields
    in order with descriptions, defaults, types, bounds and choices."""
    return json.loads(_asperity.describe(job))


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (set, frozenset)):
        return sorted(value)
    if isinstance(value, PurePath):
        return str(value)
    raise TypeError(f"{type(value).__name__} is not a parameter value")


def to_json(fields: Dict[str, Any]) -> str:
    """Keyword arguments as the engine's JSON (tuples as lists, numpy scalars as numbers).
    NaN and ±inf are refused naming the keyword, as the engine refuses them from a flag."""
    try:
        return json.dumps(fields, default=_jsonable, allow_nan=False)
    except ValueError:
        for name, value in fields.items():
            try:
                json.dumps(value, default=_jsonable, allow_nan=False)
            except ValueError:
                raise ValueError(f"{name} must be a finite number, got {value!r}") from None
        raise


_JSON_TYPES = {"integer": "int", "number": "float", "string": "str", "boolean": "bool", "array": "list"}


def _type(t, field: dict) -> str:
    if t == "array":
        item = _JSON_TYPES.get((field.get("items") or {}).get("type"), "Any")
        return f"Sequence[{item}]"
    return _JSON_TYPES.get(t, "Any")


def annotation(field: dict) -> str:
    """The field's Python type as text (for docs and stubs)."""
    t = field.get("type")
    if "choices" in field:
        text = "Literal[" + ", ".join(repr(c["value"]) for c in field["choices"]) + "]"
    elif isinstance(t, list):
        text = "Union[" + ", ".join(_type(x, field) for x in t) + "]"
    else:
        text = _type(t, field)
    return f"Optional[{text}]" if field.get("nullable") and not field.get("required") else text


def _bounds(field: dict) -> str:
    words = []
    for key, word in (("minimum", "≥"), ("exclusiveMinimum", ">"), ("maximum", "≤"),
                      ("exclusiveMaximum", "<")):
        if key in field:
            words.append(f"{word} {field[key]:g}" if isinstance(field[key], float) else f"{word} {field[key]}")
    return ", ".join(words)


def field_doc(field: dict) -> str:
    """One field's line in a docstring: description, choices, bounds, default."""
    text = field["description"].replace("\n", " ").rstrip(".")
    extras = []
    if "choices" in field:
        extras.append("one of " + ", ".join(repr(c["value"]) for c in field["choices"]))
    bounds = _bounds(field)
    if bounds:
        extras.append(bounds)
    extras.append("required" if field.get("required") else f"default {field['default']!r}")
    return f"{field['name']}: {text} ({'; '.join(extras)})."


class ArrayResult(np.ndarray):
    """An array that a job returned, with the job's ``params``."""

    params: Optional[dict] = None

    def __array_finalize__(self, obj):
        self.params = getattr(obj, "params", None)


class Job:
    """How one engine job is called from Python.

    ``leading``: required positional inputs ``(name, doc)`` or ``(name, doc,
    convert)`` (a function that prepares the value for the engine); ``inputs``:
    keyword-only inputs and output choices ``(name, default, doc)`` that are
    not parameters (meshes, images, ``points=True``); ``engine``: the
    binding's function, called as ``engine(params_json, *leading, *inputs,
    threads, progress=…)`` with the seed among the parameters (seeded jobs);
    ``finish`` turns its dict into the result.
    """

    def __init__(self, job: str, engine: Callable, finish: Callable[[dict], Any], *, name: str,
                 summary: str, returns: str, leading: Sequence[tuple] = (),
                 inputs: Sequence[Tuple[str, Any, str]] = (), threads: bool = True,
                 progress: bool = True, convert: Optional[Dict[str, Callable]] = None,
                 prepare: Optional[Callable[[dict], dict]] = None, record: bool = True,
                 result: str = "Result"):
        self.job, self.engine, self.finish = job, engine, finish
        self.name, self.summary, self.returns = name, summary, returns
        self.leading, self.inputs = list(leading), list(inputs)
        self.threads, self.progress = threads, progress
        self.convert = convert or {}
        self.prepare = prepare or (lambda fields: fields)
        self.record = record
        self.result = result
        self.description = describe(job)
        self.fields = [f["name"] for f in self.description["fields"]]

    def signature(self) -> inspect.Signature:
        ps = [P(n, P.POSITIONAL_OR_KEYWORD) for n, *_ in self.leading]
        ps += [P(f["name"], P.POSITIONAL_OR_KEYWORD)
               for f in self.description["fields"] if f.get("required")]
        ps += [P(f["name"], P.POSITIONAL_OR_KEYWORD, default=f["default"])
               for f in self.description["fields"] if not f.get("required")]
        ps += [P(n, P.KEYWORD_ONLY, default=d) for n, d, _ in self.inputs]
        if self.description["seeded"]:
            ps.append(P("seed", P.KEYWORD_ONLY, default=DEFAULT_SEED))
        if self.threads:
            ps.append(P("threads", P.KEYWORD_ONLY, default=None))
        if self.progress:
            ps.append(P("progress", P.KEYWORD_ONLY, default=False))
        ps.append(P("params", P.VAR_KEYWORD))
        return inspect.Signature(ps)

    def doc(self) -> str:
        lines = [self.summary, "", f"Parameters (the engine's; the CLI's ``{self.job}`` flags):"]
        lines += [f"    {n}: {d}" for n, d, *_ in self.leading]
        lines += ["    " + field_doc(f) for f in self.description["fields"]]
        lines += [f"    {n}: {d}" for n, _, d in self.inputs]
        if self.description["seeded"]:
            lines.append(f"    seed: random seed (default {DEFAULT_SEED}, as the CLI's ``--seed``).")
        if self.threads:
            lines.append("    threads: worker threads (default: every core; results do not depend on it).")
        if self.progress:
            lines.append("    progress: True for a tqdm bar, or a callable (done, total, message).")
        lines.append("    **params: a result's ``params`` (a record of a run) to run it again.")
        lines += ["", self.returns, "",
                  "Every result has ``params``: the job, schema version, seed and every value it ran with."]
        return "\n".join(lines)

    def function(self) -> Callable:
        sig = self.signature()

        def run(*args, **kwargs):
            bound = sig.bind(*args, **kwargs)
            given = dict(bound.arguments)
            fields = {k: given.pop(k) for k in self.fields if k in given}
            fields.update(given.pop("params", {}))
            fields = self.prepare(fields)
            seed = given.pop("seed", DEFAULT_SEED)
            threads = given.pop("threads", None)
            progress = given.pop("progress", False)
            lead = [(conv[0] if conv else (lambda v: v))(given.pop(n)) for n, _, *conv in self.leading]
            extra = [self.convert.get(n, lambda v: v)(given.pop(n, d)) for n, d, _ in self.inputs]
            if fields.setdefault("job", self.job) != self.job:
                raise ValueError(f"these parameters are for {fields['job']!r}, not {self.job!r}")
            if self.description["seeded"]:
                fields["seed"] = seed
            args = [to_json(fields), *lead, *extra]
            if self.threads:
                args.append(threads)
            if self.progress:
                raw = call(self.engine, *args, progress=progress)
            else:
                raw = self.engine(*args)
            result = self.finish(raw)
            if self.record and isinstance(raw, dict) and "params" in raw:
                record = json.loads(raw["params"])
                if isinstance(result, dict):
                    result["params"] = record
                    # the surfaces inside carry it too, into the files they are saved to
                    # (marked by ``types._Surface``, not imported here: types renders
                    # through ``_pictures``, a job)
                    for value in result.values():
                        if getattr(type(value), "carries_params", False):
                            value.params = record
                elif isinstance(result, np.ndarray):
                    result = result.view(ArrayResult)
                    result.params = record
                else:
                    result.params = record
            return result

        run.__name__ = run.__qualname__ = self.name
        run.__module__ = "asperity"
        run.__signature__ = sig
        run.__doc__ = self.doc()
        run.job = self.job
        run.result = self.result
        return run
