"""The subdivision kinds of Add > Mesh > Rough surface: the engine's built-in
example scenes (``asperity_subdiv::examples``, which ``asperity subdiv
example:NAME`` runs too: rock, berry, tentacle, mushroom planet, spurs), with
their levels, seed, main detail size and spacing exposed. The add-on types
none of them (#36): the list and the descriptions come with the engine's
defaults (``defaults.py``), the scene text from the engine itself."""
from __future__ import annotations

from .defaults import subdiv_examples


def kinds() -> list:
    """(name, label, description) of every example, in the engine's order."""
    return [(e["name"], e["name"].title(), e["description"]) for e in subdiv_examples()]


def scene(asp, kind: str, levels: int, seed: int, size=None, spacing=None) -> str:
    """The scene text of example ``kind`` with ``levels``, ``seed`` and, where
    given, the main detail's size and spacing (ignored by an example that
    places its detail otherwise)."""
    example = next(e for e in subdiv_examples() if e["name"] == kind)
    if example["spacing"] is None:
        spacing = None
    return asp._asperity.subdiv_example(kind, int(levels), int(seed), size, spacing)
