"""``render``: pictures of surfaces, made by the engine's ``render`` job. A
module of its own so that the surface types (``Mesh.render``, Jupyter's
``_repr_png_``) and the API both use it without importing each other."""

from __future__ import annotations

from . import _asperity
from ._jobs import Job

render = Job(
    "render", _asperity.render, lambda d: d["image"], name="render", result="np.ndarray",
    summary="A picture of a surface (the CLI's ``render``: headless, on the CPU, the gobron-chiba "
            "light model), or a map or hillshade of a height field.",
    leading=[("surface", "a :class:`Mesh`, :class:`HeightField` or :class:`PointSet`.")],
    returns="Returns the picture as an (H, W, 4) uint8 array (with ``params``).",
    progress=False,
).function()
