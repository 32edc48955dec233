"""Builds the JPK seeds (fuzz/seeds/jpk) and crates/io/tests/data/small.jpk: TIFFs to
SurfaceTopography's JPK.py layout, with the builder check_instruments.py uses
(python/tests/reference/tiff_build.py).
Usage: python3 fuzz/jpk_seed.py OUT_DIR"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python/tests/reference"))
from tiff_build import jpk_bytes  # noqa: E402

out = sys.argv[1]
open(out + "/r0.jpk", "wb").write(jpk_bytes(np.arange(6).reshape(2, 3) - 2, 0))
open(out + "/r1.jpk", "wb").write(jpk_bytes(np.arange(6).reshape(2, 3) - 2, 1))
