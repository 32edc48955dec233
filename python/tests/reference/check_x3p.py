"""ISO 25178-72 .x3p both ways with two independent implementations (issue #24):
SurfaceTopography's reader and writer, and x3pio (which also verifies the MD5
checksums and the document's structure).

1. asperity writes a field in µm/nm with a non-zero origin; both libraries read
   the same size, increments (metres), offsets and heights (float64: equal to
   1e-15 of the largest height).
2. Both libraries write x3p files (float64, and int16/int32 with a height
   increment and offset; x3pio with x/y offsets); asperity reads them with the heights each library
   reads back from its own file (1e-12 relative), the same increments and
   offsets, and units of metres.

Usage: python check_x3p.py ASPERITY_BINARY WORKDIR
"""
import sys
from pathlib import Path

import numpy as np
import x3pio
from SurfaceTopography import Topography, read_topography

from checks import check, finish, info, run, write_csv_field

BIN, WORK = sys.argv[1], Path(sys.argv[2])
WORK.mkdir(parents=True, exist_ok=True)
nx, ny, dx, dy, x0, y0 = 48, 36, 0.25, 0.5, 10.0, -3.0  # µm
rng = np.random.default_rng(11)
z = np.cumsum(rng.normal(size=(ny, nx)), axis=0) * 3.0 + 100.0  # nm
def close(a, b, rel):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a.shape == b.shape and np.max(np.abs(a - b)) <= rel * np.max(np.abs(b))


# 1. asperity writes, SurfaceTopography and x3pio read.
write_csv_field(WORK / "field.csv", z, dx, dy, x0, y0)
ours = WORK / "asperity.x3p"
run(BIN, "--quiet", "--xy-unit", "µm", "--z-unit", "nm", "convert", WORK / "field.csv", ours)
metres = z * 1e-9

t = read_topography(str(ours))
check("SurfaceTopography: size", t.nb_grid_pts == (nx, ny), str(t.nb_grid_pts))
check("SurfaceTopography: extent in metres", close(t.physical_sizes, [nx * dx * 1e-6, ny * dy * 1e-6], 1e-12)
      and t.unit == "m", f"{t.physical_sizes} {t.unit}")
check("SurfaceTopography: heights", close(t.heights().T, metres, 1e-15))

x = x3pio.read(ours)
layer = x.layers[0]
check("x3pio: a surface, one layer", type(x).__name__ == "Surface" and len(x.layers) == 1)
check("x3pio: heights", close(layer.z, metres, 1e-15))
check("x3pio: increments", close(layer.spacing, [dx * 1e-6, dy * 1e-6], 1e-12), str(layer.spacing))
check("x3pio: offsets", close(layer.placement.offset[:2], [x0 * 1e-6, y0 * 1e-6], 1e-12),
      str(layer.placement.offset))

# 2. SurfaceTopography and x3pio write, asperity reads.
written = []
for dtype in ["D", "I", "L"]:
    path = WORK / f"st_{dtype}.x3p"
    Topography(metres.T, (nx * dx * 1e-6, ny * dy * 1e-6), unit="m").to_x3p(str(path), dtype=dtype)
    written.append((f"SurfaceTopography {dtype}", path, read_topography(str(path)).heights().T,
                    [dx * 1e-6, dy * 1e-6], [0.0, 0.0]))
for z_type in [x3pio.DataType.FLOAT64, x3pio.DataType.INT16]:
    path = WORK / f"x3pio_{z_type.name}.x3p"
    placement = x3pio.Placement(offset=[x0 * 1e-6, y0 * 1e-6, 0.0])  # CX/CY Offset
    x3pio.write(path, metres, x_scale=dx * 1e-6, y_scale=dy * 1e-6, z_type=z_type, placement=placement,
                coordinate_system=x3pio.CoordinateSystem.VIEW)
    written.append((f"x3pio {z_type.name}", path, x3pio.read(path).layers[0].z, [dx * 1e-6, dy * 1e-6],
                    [x0 * 1e-6, y0 * 1e-6]))

for name, path, truth, spacing, origin in written:
    npy = path.with_suffix(".npy")
    run(BIN, "--quiet", "convert", path, npy)
    check(f"asperity reads {name}: heights", close(np.load(npy), truth, 1e-12))
    facts = info(BIN, path)
    check(f"asperity reads {name}: increments, offsets, metres",
          close(facts["spacing"], spacing, 1e-12) and np.allclose(facts["origin"], origin, rtol=0, atol=1e-18)
          and facts["units"] == {"xy": "m", "z": "m"}, f"{facts['spacing']} {facts['origin']} {facts['units']}")

finish()
