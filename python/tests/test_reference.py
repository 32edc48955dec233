"""Against outside truth: surfaces from SurfaceTopography's own generator,
analysed from numpy, agree with SurfaceTopography's spectra; meshes the CLI
calls watertight are watertight in trimesh."""

import numpy as np
import pytest
import trimesh
from SurfaceTopography import Topography
from SurfaceTopography.Generation import fourier_synthesis

import asperity


def st_surface(n, hurst, seed):
    rng = np.random.default_rng(seed)
    h = fourier_synthesis((n, n), (n, n), hurst=hurst, rms_height=1.0, rng=rng).heights()
    return np.ascontiguousarray(h)  # indexed [x, y]


@pytest.mark.parametrize("hurst,seed", [(0.8, 1), (0.5, 2), (0.3, 3)])
def test_psd_and_hurst_of_surfacetopography_fbm(hurst, seed):
    h = st_surface(256, hurst, seed)
    # asperity's heights are (ny, nx): SurfaceTopography's [x, y] array transposed
    m = asperity.analyze(h.T.copy())
    p = m["psd"]
    topo = Topography(h, (256, 256), periodic=True)
    _, _, c_map = topo.power_spectrum_from_area(window="None" if m["window"] == "none" else m["window"],
                                                 return_map=True)
    qx = 2 * np.pi * np.fft.fftfreq(256, 1.0)
    q_map = np.hypot(qx[:, None], qx[None, :]).ravel()
    c_map = c_map.ravel()
    edges = p["q_edges"]
    ref_q, ref_c, ref_n = [], [], []
    for k, (lo, hi) in enumerate(edges):
        last = k == len(edges) - 1
        qt = q_map * (1 + 1e-9)
        sel = (qt >= lo) & ((q_map <= hi * (1 + 1e-12)) if last else (qt < hi))
        if sel.sum() >= 50:
            assert p["C"][k] == pytest.approx(c_map[sel].mean(), rel=0.02), f"bin {k}"
        if sel.any():
            ref_q.append(q_map[sel].mean())
            ref_c.append(c_map[sel].mean())
            ref_n.append(sel.sum())
    # H from SurfaceTopography's spectrum, averaged in the same bins and
    # fitted over asperity's range, each bin weighted by its modes (a bin mean
    # of n modes has a relative scatter ∝ 1/√n): C ∝ q^(−2(1+H))
    lo, hi = m["hurst_estimates"]["psd_2d"]["fit_range"]
    q, C, n = np.array(ref_q), np.array(ref_c), np.array(ref_n, dtype=float)
    ok = (q >= lo) & (q <= hi)
    slope = np.polyfit(np.log(q[ok]), np.log(C[ok]), 1, w=np.sqrt(n[ok]))[0]
    h_st = -slope / 2 - 1
    assert m["hurst"] == pytest.approx(h_st, abs=0.05)
    assert m["hurst"] == pytest.approx(hurst, abs=0.05)
    q2, C2 = asperity.psd(h.T.copy())
    assert np.array_equal(C2, np.asarray(p["C"]))
    H, estimates = asperity.hurst(h.T.copy())
    assert H == m["hurst"] and "psd_2d" in estimates


def test_sq_matches_surfacetopography():
    h = st_surface(128, 0.7, 5)
    m = asperity.analyze(h.T.copy(), level="mean")
    topo = Topography(h, (128, 128), periodic=True)
    assert m["Sq"] == pytest.approx(topo.rms_height_from_area(), rel=1e-9)


def test_meshes_watertight_in_trimesh_where_the_cli_says_so(cli, tmp):
    cases = [
        asperity.dla_terrain(size=(24, 24, 24), particles=600, iterations=10, seed=4).mesh,
        asperity.rdsr_sphere(radius=8, layers=2, resolution=24, seed=1).mesh,
        asperity.subdiv(base="cube", levels=2, detail=["rock"]).mesh,
        asperity.ifs_surface("takagi-square", depth=4),  # an open sheet
    ]
    for k, m in enumerate(cases):
        m.save(tmp / f"m{k}.ply")
        said = cli("info", tmp / f"m{k}.ply")["measurements"]["watertight"]
        t = m.to_trimesh()
        assert t.is_watertight == said, f"case {k}: trimesh {t.is_watertight}, CLI {said}"
    assert cases[0].to_trimesh().is_watertight and not cases[3].to_trimesh().is_watertight
