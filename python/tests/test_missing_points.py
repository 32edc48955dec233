"""Missing (unmeasured) points of measured data (issue #38): NaN heights in
Python, as in numpy, carried by load/save and analyze, refused where a step
needs every point.

The file is Digital Surf's sur-2.sur from SurfaceTopography's examples, whose
reader masks the same 117 points (python/tests/reference/check_instruments.py).
"""
from pathlib import Path

import numpy as np
import pytest

import asperity

SUR = Path(__file__).resolve().parents[2] / "tests/data/surfacetopography/sur-2.sur"
MISSING = 117


def test_load_gives_nan_where_the_instrument_measured_nothing():
    h = asperity.load(SUR)
    assert h.heights.shape == (484, 563)
    assert int(np.isnan(h.heights).sum()) == MISSING
    assert np.isfinite(h.heights[~np.isnan(h.heights)]).all()


def test_analyze_reports_over_the_measured_points_or_refuses():
    h = asperity.load(SUR)
    r = asperity.analyze(h, level="mean", hurst="psd")
    assert r["missing"]["count"] == MISSING
    assert r["missing"]["fill"] == "harmonic"
    z = h.heights[~np.isnan(h.heights)]
    assert r["Sq"] == pytest.approx(np.sqrt(np.mean((z - z.mean()) ** 2)), rel=1e-12)
    with pytest.raises(ValueError, match=f"{MISSING} of {h.heights.size} points were not measured"):
        asperity.analyze(h, fill="refuse")


def test_formats_that_mark_points_keep_them_and_png_refuses(tmp_path):
    h = asperity.load(SUR)
    for ext in ["npy", "x3p", "gwy", "gsf"]:
        h.save(tmp_path / f"copy.{ext}")
        back = asperity.load(tmp_path / f"copy.{ext}")
        assert np.array_equal(np.isnan(back.heights), np.isnan(h.heights)), ext
    with pytest.raises(ValueError, match="not measured"):
        h.save(tmp_path / "copy.png")
    assert not (tmp_path / "copy.png").exists()


def test_a_numpy_array_with_nan_is_a_field_with_missing_points():
    z = np.add.outer(np.arange(8.0), np.arange(10.0))
    z[3, 4] = np.nan
    r = asperity.analyze(asperity.HeightField(z), hurst="psd")
    assert r["missing"]["count"] == 1
    with pytest.raises(ValueError, match="not finite"):
        asperity.HeightField(np.where(np.isnan(z), np.inf, z)).save("never.npy")
