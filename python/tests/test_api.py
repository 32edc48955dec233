"""The package's surface: documented functions, stubs that match the module,
Jupyter pictures, trimesh export, the CLI's defaults."""

import ast
import inspect
from pathlib import Path

import numpy as np

from conftest import same_bytes

import asperity
from asperity import _asperity
from asperity._jobs import describe


def test_every_public_function_is_documented_with_defaults():
    for name in asperity.__all__:
        obj = getattr(asperity, name)
        assert obj.__doc__ and len(obj.__doc__) > 40, name
        if inspect.isfunction(obj):
            for p in inspect.signature(obj).parameters.values():
                if p.kind is p.POSITIONAL_OR_KEYWORD and p.name not in ("surface", "points",
                                                                        "heights", "mesh", "rule",
                                                                        "steps", "path", "method", "image"):
                    assert p.default is not p.empty, f"{name}({p.name}) has a default"


def test_stubs_cover_the_extension_module():
    stub = Path(_asperity.__file__).with_name("_asperity.pyi")
    if not stub.exists():  # the assembled test package keeps it beside the module
        stub = Path(asperity.__file__).with_name("_asperity.pyi")
    tree = ast.parse(stub.read_text())
    stubbed = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
    native = {n for n in dir(_asperity) if not n.startswith("_") and callable(getattr(_asperity, n))}
    assert native == stubbed


def test_jupyter_pictures_and_trimesh():
    m = asperity.subdiv(base="cube", levels=2).mesh
    png = m._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 1000
    assert asperity.fbm(size=32)._repr_png_()[:4] == b"\x89PNG"
    t = m.to_trimesh()
    assert t.is_watertight and len(t.faces) == m.n_faces
    np.testing.assert_array_equal(t.vertices, m.vertices)


def test_arrays_are_numpy_native():
    r = asperity.rdsr(size=64, layers=10, points=True)
    for a in (r.heights, r.points.points):
        assert a.flags.c_contiguous and a.dtype == np.float64
    m = asperity.reconstruct(r.points, resolution=24).mesh
    assert m.faces.dtype == np.uint32 and m.vertices.shape[1] == 3
    assert m.normals is not None and m.normals.shape == m.vertices.shape


def test_defaults_are_the_clis(cli, tmp):
    """With no flags, the CLI and the Python defaults give the same bytes."""
    cli("generate", "fbm", "-o", tmp / "c.npy")
    asperity.fbm().save(tmp / "p.npy")
    assert (tmp / "c.npy").read_bytes() == (tmp / "p.npy").read_bytes()
    cli("growth", "rdsr", "--layers", 5, "-o", tmp / "c.npy")
    asperity.rdsr(layers=5).surface.save(tmp / "p.npy")
    assert (tmp / "c.npy").read_bytes() == (tmp / "p.npy").read_bytes()
    cli("subdiv", "--triangles", "-o", tmp / "c.ply")
    asperity.subdiv().mesh.save(tmp / "p.ply")
    assert (tmp / "c.ply").read_bytes() == (tmp / "p.ply").read_bytes()
    cli("ifs", "surface", "--preset", "bezier-bicubic", "-o", tmp / "c.ply")
    asperity.ifs_surface("bezier-bicubic").save(tmp / "p.ply")
    assert (tmp / "c.ply").read_bytes() == (tmp / "p.ply").read_bytes()


def test_signatures_show_the_engines_defaults():
    """Every job's function takes the engine's fields with the engine's
    defaults (issue #36): no default is restated in Python."""
    jobs = set(_asperity.jobs())
    seen = set()
    for name in dir(asperity):
        f = getattr(asperity, name)
        job = getattr(f, "job", None)
        if job is None:
            continue
        seen.add(job)
        params = inspect.signature(f).parameters
        desc = describe(job)
        for field in desc["fields"]:
            if field["name"] in ("scene_text", "model") and field["name"] not in params:
                continue
            p = params[field["name"]]
            if field["required"]:
                assert p.default is p.empty, f"{name}({p.name}) is required"
            else:
                assert p.default == field["default"], f"{name}({p.name})"
        if desc["seeded"]:
            assert params["seed"].default == _asperity.DEFAULT_SEED
    # every job Python runs is one of the engine's (ca gallery, interpolate,
    # convert and info are the CLI's, or plain functions here)
    assert seen <= jobs and len(seen) >= 21, sorted(jobs - seen)


def test_stubs_are_the_engines():
    """``__init__.pyi`` is what ``python -m asperity._stubs`` writes from the
    engine's descriptions (regenerate it after changing a job's parameters)."""
    from asperity._stubs import stub_text

    committed = Path(asperity.__file__).with_name("__init__.pyi").read_text()
    assert committed == stub_text(), "stale stubs: python -m asperity._stubs > python/asperity/__init__.pyi"
    ast.parse(committed)


def test_files_keep_the_parameters_that_make_them_again(cli, tmp):
    """A saved surface records its job's params (#36): loading the file gives
    them back, they make the same bytes again, and the CLI reads them too."""
    h = asperity.fbm(size=48, hurst=0.55, rms=0.3, seed=11)
    for ext in ("gsf", "png", "exr", "x3p", "gwy", "csv"):
        h.save(tmp / f"h.{ext}")
        assert asperity.load(tmp / f"h.{ext}").params == h.params, ext
    assert asperity.load(tmp / "h.gsf").params["seed"] == 11
    again = asperity.fbm(**asperity.load(tmp / "h.gsf").params)
    again.save(tmp / "again.gsf")
    same_bytes(tmp / "h.gsf", tmp / "again.gsf")
    cli("generate", "fbm", "--params", tmp / "h.gsf", "-o", tmp / "cli.gsf")
    same_bytes(tmp / "h.gsf", tmp / "cli.gsf")
    assert cli("info", tmp / "h.x3p")["measurements"]["made_with"] == h.params
    # a surface inside a result, and a picture
    r = asperity.rdsr(layers=4, size=24, seed=2)
    r.surface.save(tmp / "r.ply")
    assert asperity.load(tmp / "r.ply").params == r.params
    img = asperity.render(h, size=(64, 48))
    asperity.save_image(tmp / "render.png", img)
    assert cli("info", tmp / "render.png")["measurements"]["made_with"] == img.params
    # a file without a record: none, and --params says so
    asperity.save(tmp / "bare.npy", asperity.HeightField(np.zeros((4, 4))))
    assert asperity.load(tmp / "bare.npy").params is None
    p = cli("generate", "fbm", "--params", tmp / "bare.npy", "-o", tmp / "x.gsf", check=False)
    assert p.returncode != 0 and "records no parameters" in p.stderr
