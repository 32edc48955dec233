"""Every method family: the Python result, written by asperity.save, equals
the CLI's output for the same seed byte for byte, and the measurements are the
CLI's."""

import json

import numpy as np
import pytest

import asperity
from conftest import same_bytes, same_bytes_but_params


def strip_timing(m):
    drop = {"elapsed_s", "seconds", "timings_s", "build_s", "write_s", "cells_s", "file",
            "cell_updates_per_second", "build_and_write_s", "run_s", "cell_updates_per_s",
            "walkers"}  # DLA: walks in flight and redone follow the threads' timing
    if isinstance(m, dict):
        return {k: strip_timing(v) for k, v in m.items() if k not in drop}
    if isinstance(m, list):
        return [strip_timing(v) for v in m]
    return m


@pytest.mark.parametrize("model", ["rd", "rdsr", "bd"])
def test_deposition_heights_points_and_measurements(cli, tmp, model):
    rep = cli("--seed", 7, "growth", model, "--size", 32, "--layers", 20, "-o", tmp / "c.gsf",
              "--points", tmp / "c.ply")
    r = getattr(asperity, model)(size=32, layers=20, seed=7, points=True)
    r.surface.save(tmp / "p.gsf")
    r.points.save(tmp / "p.ply")
    same_bytes(tmp / "c.gsf", tmp / "p.gsf")
    same_bytes(tmp / "c.ply", tmp / "p.ply")
    assert strip_timing(r.measurements) == strip_timing(rep["measurements"])
    assert r.beta == rep["measurements"]["beta"]
    assert r.heights.shape == (32, 32)


def test_deposition_1d_and_curved(cli, tmp):
    cli("--seed", 3, "growth", "rdsr", "--dim", 1, "--size", 64, "--layers", 50, "-o", tmp / "c.npy")
    r = asperity.rdsr(dim=1, size=64, layers=50, seed=3)
    assert r.heights.shape == (64,)
    np.testing.assert_array_equal(np.load(tmp / "c.npy"), r.heights)
    cli("--seed", 3, "growth", "bd", "--substrate", "sphere", "--radius", 8, "--layers", 3,
        "-o", tmp / "s.ply")
    s = asperity.bd(substrate="sphere", radius=8, layers=3, seed=3)
    s.points.save(tmp / "p.ply")
    same_bytes(tmp / "s.ply", tmp / "p.ply")


@pytest.mark.parametrize("shape", ["point", "plane", "sphere"])
def test_dla(cli, tmp, shape):
    rep = cli("--seed", 5, "growth", "dla", "--seed-shape", shape, "--particles", 400,
              "--size", "40x40x40", "-o", tmp / "c.ply")
    r = asperity.dla(seed_shape=shape, particles=400, size=(40, 40, 40), seed=5)
    r.points.save(tmp / "p.ply")
    same_bytes(tmp / "c.ply", tmp / "p.ply")
    assert strip_timing(r.measurements) == strip_timing(rep["measurements"])


def test_dla_walkers(cli, tmp):
    """``walkers=`` is the CLI's ``--walkers``: the same cluster, the concurrency reported."""
    one = asperity.dla(particles=600, seed=3)
    many = asperity.dla(particles=600, seed=3, walkers=6)
    assert np.array_equal(one.points.points, many.points.points)
    assert many.measurements["walkers"]["walkers"] == 6
    assert "walkers" not in many.params
    with pytest.raises(ValueError, match="walkers= must be at least 1"):
        asperity.dla(particles=10, walkers=0)


def test_dla_seeded_by_mesh_and_image_arrays(cli, tmp):
    """Seeds from arrays equal the CLI's seeds from the same data in files."""
    cube = asperity.subdiv(base="cube", levels=1)
    cube.mesh.save(tmp / "seed.ply")
    cli("--seed", 2, "growth", "dla", "--seed-shape", "mesh", "--mesh", tmp / "seed.ply",
        "--particles", 300, "-o", tmp / "c.ply")
    r = asperity.dla(seed_shape="mesh", mesh=asperity.load(tmp / "seed.ply"), particles=300, seed=2)
    r.points.save(tmp / "p.ply")
    same_bytes(tmp / "c.ply", tmp / "p.ply")
    img = np.zeros((24, 24))
    img[8:16, 8:16] = 1.0
    asperity.HeightField(img).save(tmp / "img.npy")
    cli("--seed", 2, "growth", "dla", "--seed-shape", "image", "--image", tmp / "img.npy",
        "--particles", 200, "--size", "24x24x30", "--seed-density", 0.5, "-o", tmp / "ci.ply")
    r = asperity.dla(seed_shape="image", image=asperity.HeightField(img), particles=200,
                     size=(24, 24, 30), seed_density=0.5, seed=2)
    r.points.save(tmp / "pi.ply")
    same_bytes(tmp / "ci.ply", tmp / "pi.ply")


def test_reconstruct_and_pipelines(cli, tmp):
    cli("--seed", 1, "growth", "dla", "--particles", 300, "--size", "32x32x32", "-o", tmp / "d.ply")
    rep = cli("reconstruct", tmp / "d.ply", "--resolution", 32, "--offset", "3h", "-o", tmp / "c.ply")
    pts = asperity.load(tmp / "d.ply")
    r = asperity.reconstruct(pts, resolution=32, offset="3h")
    r.mesh.save(tmp / "p.ply")
    same_bytes(tmp / "c.ply", tmp / "p.ply")
    assert r.measurements["watertight"] == rep["measurements"]["watertight"]
    assert strip_timing(r.measurements) == strip_timing(rep["measurements"])

    cli("--seed", 4, "generate", "rdsr-sphere", "--radius", 8, "--layers", 2, "--resolution", 24,
        "-o", tmp / "cs.ply")
    s = asperity.rdsr_sphere(radius=8, layers=2, resolution=24, seed=4)
    s.mesh.save(tmp / "ps.ply")
    same_bytes(tmp / "cs.ply", tmp / "ps.ply")

    cli("--seed", 4, "generate", "dla-terrain", "--size", "24x24x24", "--particles", 600,
        "--iterations", 10, "-o", tmp / "ct.ply")
    t = asperity.dla_terrain(size=(24, 24, 24), particles=600, iterations=10, seed=4)
    t.mesh.save(tmp / "pt.ply")
    same_bytes(tmp / "ct.ply", tmp / "pt.ply")


def test_ca_run_facet_interpolate(cli, tmp):
    rep = cli("--seed", 9, "ca", "run", "--rule", "450", "--steps", 24, "--init", "random:0.3", "--size", "40x30",
              "-o", tmp / "c.gsf")
    r = asperity.ca_run(450, 24, init="random:0.3", size=(40, 30), seed=9)
    r.surface.save(tmp / "p.gsf")
    same_bytes(tmp / "c.gsf", tmp / "p.gsf")
    assert strip_timing(r.measurements) == strip_timing(rep["measurements"])
    cli("facet", tmp / "c.gsf", "--circle", "20,15,8", "-o", tmp / "fc.obj")
    f = asperity.facet(r.surface, circle=(20, 15, 8))
    assert len(f.curves) == 1 and f.curves[0].shape[1] == 3
    cli("facet", tmp / "c.gsf", "-o", tmp / "fc.ply")
    asperity.facet(r.surface).mesh.save(tmp / "fp.ply")  # (circle= gives the same mesh)
    same_bytes(tmp / "fc.ply", tmp / "fp.ply")
    xy = np.array([[1.5, 2.25], [10.0, 7.5], [-3.0, 1.0]])
    np.savetxt(tmp / "xy.csv", xy, delimiter=",")
    out = cli("interpolate", tmp / "c.gsf", "--points", tmp / "xy.csv")
    z = asperity.interpolate(r.surface, xy)
    np.testing.assert_allclose(z, np.array(out["measurements"]["points"], dtype=float)[:, 2])
    assert np.isnan(z[2])
    assert asperity.ca_rule(450).measurements == cli("ca", "rule", "450")["measurements"]


def test_subdiv_options_and_scene(cli, tmp):
    cli("--seed", 3, "subdiv", "--base", "cube", "--levels", 3, "--detail", "rock:amplitude=0.1",
        "--triangles", "-o", tmp / "c.ply")
    r = asperity.subdiv(base="cube", levels=3, detail=["rock:amplitude=0.1"], seed=3)
    r.mesh.save(tmp / "p.ply")
    same_bytes(tmp / "c.ply", tmp / "p.ply")
    assert r.levels[-1][1] == 6 * 4**3
    from pathlib import Path
    scene = Path(__file__).resolve().parents[2] / "crates/subdiv/scenes/rock.toml"
    cli("--seed", 2, "subdiv", scene, "--triangles", "-o", tmp / "cs.ply")
    s = asperity.subdiv(scene, seed=2)
    s.mesh.save(tmp / "ps.ply")
    same_bytes(tmp / "cs.ply", tmp / "ps.ply")
    t = asperity.subdiv(scene.read_text(), seed=2)  # the TOML text itself
    t.mesh.save(tmp / "pt.ply")
    same_bytes_but_params(tmp / "cs.ply", tmp / "pt.ply")  # the record names the text, not the file


def test_ifs_surface_dcf_sdcf_curvature(cli, tmp):
    cli("ifs", "surface", "--preset", "takagi-square", "--depth", 5, "-o", tmp / "c.ply")
    m = asperity.ifs_surface("takagi-square", depth=5)
    m.save(tmp / "p.ply")
    same_bytes(tmp / "c.ply", tmp / "p.ply")
    cli("ifs", "dcf", "--preset", "bezier-cubic", "--operator", 1, "--samples", 64,
        "-o", tmp / "d.csv")
    d = asperity.ifs_dcf("bezier-cubic", operator=1, samples=64)
    ref = np.loadtxt(tmp / "d.csv", delimiter=",", skiprows=1)[:, 1:]
    np.testing.assert_allclose(d.points, ref, rtol=1e-12, atol=1e-15)
    cli("ifs", "sdcf", "--preset", "takagi-square", "--resolution", 16, "-o", tmp / "s.ply")
    asperity.ifs_sdcf("takagi-square", resolution=16).save(tmp / "ps.ply")
    same_bytes(tmp / "s.ply", tmp / "ps.ply")
    doc = cli("ifs", "curvature", "--preset", "takagi-landsberg", "--at", "0.5")
    mine = asperity.ifs_curvature("takagi-landsberg", at=[0.5])
    assert strip_timing(mine) == strip_timing(doc)
    # a custom model from arrays: the preset's own file, edited, passed back
    f = asperity.ifs_model("bezier-quadratic")
    f["name"] = "mine"
    f["curve"]["control_points"] = np.array(f["curve"]["control_points"])  # arrays are welcome
    pts = asperity.ifs_curve(model=f, depth=6)
    assert pts.shape == (2**6 + 1, 3)
    np.testing.assert_allclose(pts, asperity.ifs_curve("bezier-quadratic", depth=6))


def test_surface_ca_voronoi_and_corrosion(cli, tmp):
    rep = cli("--seed", 6, "surface-ca", "builtin:sphere", "--cells", 3000, "--sites", 5,
              "-o", tmp / "c.glb", "--labels-out", tmp / "cl.ply")
    r = asperity.surface_ca("builtin:sphere", cells=3000, sites=5, seed=6)
    r.mesh.save(tmp / "p.glb")
    same_bytes(tmp / "c.glb", tmp / "p.glb")
    assert strip_timing(r.measurements) == strip_timing(rep["measurements"])
    assert r.mesh.texture is not None and r.mesh.texture.shape[2] == 4
    r.labels.save(tmp / "pl.ply")
    same_bytes(tmp / "cl.ply", tmp / "pl.ply")
    cli("--seed", 6, "surface-ca", "builtin:cube", "--app", "corrosion", "--steps", 40, "--cells", 2000,
        "-o", tmp / "cc.ply")
    cube = asperity.load(tmp / "cc.ply")
    c = asperity.surface_ca("builtin:cube", app="corrosion", steps=40, cells=2000, seed=6,
                            textured=False)
    c.mesh.save(tmp / "pc.ply")
    same_bytes(tmp / "cc.ply", tmp / "pc.ply")
    assert c.labels is None
    assert c.field.shape == (c.measurements["cells"],) and cube.n_faces > 0


def test_analysis_and_fbm(cli, tmp):
    cli("--seed", 11, "generate", "fbm", "--size", 128, "--hurst", 0.7, "-o", tmp / "c.npy")
    h = asperity.fbm(size=128, hurst=0.7, seed=11)
    h.save(tmp / "p.npy")
    same_bytes(tmp / "c.npy", tmp / "p.npy")
    rep = cli("analyze", tmp / "c.npy")
    mine = asperity.analyze(h)
    assert mine.pop("warnings") == rep["warnings"]
    assert mine.pop("params") == rep["params"]
    assert strip_timing(mine) == strip_timing(rep["measurements"])
    # a plain numpy array is a height field with unit spacing
    plain = asperity.analyze(np.load(tmp / "c.npy"))
    plain.pop("warnings")
    plain.pop("params")
    assert strip_timing(plain) == strip_timing(mine)
    q, C = asperity.psd(h)
    assert q.shape == C.shape and q.size > 10
    m = asperity.subdiv(base="cube", levels=2).mesh
    m.save(tmp / "m.ply")
    assert strip_timing({k: v for k, v in asperity.analyze(m).items() if k not in ("warnings", "params")}) == \
        strip_timing(cli("analyze", tmp / "m.ply")["measurements"])


def test_iso_filters_and_functional_parameters(cli, tmp):
    # the S-L surface (ISO 16610) and the material-ratio family (ISO 25178-2) the same both ways
    h = asperity.fbm(size=128, hurst=0.8, seed=12)
    h.save(tmp / "f.npy")
    rep = cli("analyze", tmp / "f.npy", "--periodic", "no", "--lambda-s", 4, "--lambda-c", 32,
              "--robust", "--filter-degree", 2, "--hurst", "psd")
    mine = asperity.analyze(h, periodic="no", lambda_s=4, lambda_c=32, robust=True,
                            filter_degree=2, hurst="psd")
    assert mine.pop("warnings") == rep["warnings"]
    assert mine.pop("params") == rep["params"]
    assert strip_timing(mine) == strip_timing(rep["measurements"])
    assert mine["filter"]["surface"] == "S-L surface" and mine["filter"]["robust_iterations"] >= 1
    assert 0 < mine["Smr1"] < mine["Smr2"] < 100
    # the filtered surface and what was removed, as files and as arrays
    cli("filter", tmp / "f.npy", tmp / "cs.npy", "--waviness", tmp / "cw.npy", "--form", tmp / "cf.npy",
        "--lambda-s", 4, "--lambda-c", 32, "--periodic", "no")
    r = asperity.filter_surface(h, lambda_s=4, lambda_c=32, periodic="no")
    r.surface.save(tmp / "ps.npy")
    r.waviness.save(tmp / "pw.npy")
    r.form.save(tmp / "pf.npy")
    for part in "swf":
        same_bytes(tmp / f"c{part}.npy", tmp / f"p{part}.npy")
    whole = r.surface.heights + r.waviness.heights + r.noise.heights + r.form.heights
    assert np.abs(whole - h.heights).max() < 1e-12


def test_render_and_load_save(cli, tmp):
    asperity.subdiv(base="cube", levels=2, detail=["rock"]).mesh.save(tmp / "m.ply")
    cli("render", tmp / "m.ply", "--size", "96x64", "-o", tmp / "c.png")
    img = asperity.render(asperity.load(tmp / "m.ply"), (96, 64))
    assert img.shape == (64, 96, 4) and img.dtype == np.uint8
    asperity.save_image(tmp / "p.png", img)
    same_bytes(tmp / "c.png", tmp / "p.png")
    # every format: the CLI's convert and load + save write the same bytes
    m = asperity.load(tmp / "m.ply")
    for ext in ["ply", "obj", "stl", "glb"]:
        cli("convert", tmp / "m.ply", tmp / f"c.{ext}")
        m.save(tmp / f"p.{ext}")
        same_bytes(tmp / f"c.{ext}", tmp / f"p.{ext}")
    # --up names the axis of every mesh file a command reads and writes: load(up=) + save(up=)
    # write the CLI's bytes, and load(up=) reads as `info --up` does
    for up, ext in [("y", "ply"), ("z", "obj"), ("y", "stl")]:
        cli("--up", up, "convert", tmp / "m.ply", tmp / f"cu.{ext}")
        asperity.load(tmp / "m.ply", up=up).save(tmp / f"pu.{ext}", up=up)
        same_bytes(tmp / f"cu.{ext}", tmp / f"pu.{ext}")
        for read_up in [None, "y", "z"]:
            flags = ["--up", read_up] if read_up else []
            bounds = cli(*flags, "info", tmp / f"pu.{ext}")["measurements"]["bounds"]
            v = asperity.load(tmp / f"pu.{ext}", up=read_up).vertices
            np.testing.assert_allclose([v.min(axis=0), v.max(axis=0)], [bounds["min"], bounds["max"]],
                                       rtol=0, atol=1e-12)
        back = asperity.load(tmp / f"pu.{ext}", up=up).vertices  # as it was read
        np.testing.assert_allclose(back.min(axis=0), asperity.load(tmp / "m.ply", up=up).vertices.min(axis=0),
                                   atol=1e-6)
    with pytest.raises(ValueError, match="y or z"):
        asperity.load(tmp / "m.ply", up="x")
    asperity.fbm(size=32).save(tmp / "h.gsf")
    h = asperity.load(tmp / "h.gsf")
    for ext in ["npy", "gsf", "csv", "exr", "png", "gwy", "x3p"]:
        cli("convert", tmp / "h.gsf", tmp / f"c.{ext}")
        h.save(tmp / f"p.{ext}")
        same_bytes(tmp / f"c.{ext}", tmp / f"p.{ext}")
    # units travel: a field in µm / nm, saved and loaded, keeps them
    hu = asperity.HeightField(h.heights, spacing=(0.5, 0.5), units=("µm", "nm"))
    for ext in ["gsf", "png", "exr", "csv", "gwy", "x3p"]:
        hu.save(tmp / f"u.{ext}")
        back = asperity.load(tmp / f"u.{ext}")
        info = cli("info", tmp / f"u.{ext}")["measurements"]
        assert back.units == (info["units"]["xy"], info["units"]["z"])
        assert back.units == (("m", "m") if ext in ("gsf", "gwy", "x3p") else ("µm", "nm")), ext
    # and what is read back is what was written
    for ext in ["npy", "gsf", "exr", "gwy", "x3p"]:
        back = asperity.load(tmp / f"p.{ext}")
        np.testing.assert_allclose(back.heights, h.heights, rtol=1e-6)


def test_built_in_example_scenes(cli, tmp):
    """``example:NAME`` is the same scene from the CLI and Python, and
    ``subdiv_examples`` lists what the engine has."""
    names = [e["name"] for e in asperity.subdiv_examples()]
    assert names == ["rock", "berry", "tentacle", "mushroom", "spur"]
    cli("--seed", 4, "subdiv", "example:tentacle", "--triangles", "-o", tmp / "c.ply")
    asperity.subdiv("example:tentacle", seed=4).mesh.save(tmp / "p.ply")
    same_bytes(tmp / "c.ply", tmp / "p.ply")
