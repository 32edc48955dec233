"""The subdivision kinds of Add > Mesh > Rough surface, as scene text for
``asperity.subdiv``: the example scenes of ``crates/subdiv/scenes`` (rock,
berry, tentacle, mushroom planet, spurs) with their main parameters exposed.
Scene syntax: ``asperity subdiv --help`` and docs in crates/subdiv."""
from __future__ import annotations

KINDS = ("rock", "berry", "tentacle", "mushroom", "spur")

DESCRIPTION = {
    "rock": "A random value per control point per level with a 1/f amplitude, on a cube (Fig. 3)",
    "berry": "Clusters of small spheres placed over a sphere, recursively (Fig. 4)",
    "tentacle": "Tapering limbs grown from a sphere, turning π/3 per level (Fig. 5)",
    "mushroom": "Caps on stems scattered over a rough sphere",
    "spur": "Spikes pushed out at the seed vertices of a level (Fig. 9)",
}

# kind: (base, levels, [detail tables]); "SIZE" and "SPACING" mark the exposed values
_SCENES = {
    "rock": ("cube", 6, [{"type": "rock", "amplitude": ("SIZE", 0.25), "decay": 0.5}]),
    "berry": ("sphere", 6, [{"type": "berry", "radius": ("SIZE", 0.3), "ratio": 0.5, "children": 5,
                             "height": 0.8, "spacing": ("SPACING", 0.7), "levels": [2, 3, 4]}]),
    "tentacle": ("sphere", 5, [{"type": "tentacle", "length": ("SIZE", 0.15), "levels": [1, 2, 3],
                                "radius": 0.35, "spacing": ("SPACING", 0.9)}]),
    "mushroom": ("sphere", 5, [{"type": "rock", "amplitude": 0.04},
                               {"type": "mushroom", "height": ("SIZE", 0.05), "radius": 0.2,
                                "spacing": ("SPACING", 0.8), "levels": [1, 2, 3, 4]}]),
    "spur": ("sphere", 5, [{"type": "spur", "height": ("SIZE", 2.5), "levels": [3],
                            "spacing": ("SPACING", 0.35)}]),
}


def _value(v, size, spacing):
    if isinstance(v, tuple):
        name, default = v
        chosen = size if name == "SIZE" else spacing
        v = default if chosen is None else chosen
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, list):
        return "[" + ", ".join(_value(x, size, spacing) for x in v) + "]"
    return repr(v)


def scene(kind: str, levels: int, seed: int, size=None, spacing=None) -> str:
    """The scene text of ``kind`` with ``levels``, ``seed`` and, where given,
    the detail's main size and spacing."""
    base, _, details = _SCENES[kind]
    lines = [f'base = "{base}"', f"levels = {int(levels)}", f"seed = {int(seed)}"]
    for d in details:
        d = dict(d)
        if "levels" in d:  # placed at the levels the surface has
            d["levels"] = [x for x in d["levels"] if x <= levels] or [1]
        lines.append("\n[[detail]]")
        lines += [f"{k} = {_value(v, size, spacing)}" for k, v in d.items()]
    return "\n".join(lines) + "\n"
