"""Zygo .datx files built with h5py to the layout Gwyddion's datxfile.c and
SurfaceTopography's DATX.py read (no instrument file is public in a
repository asperity can reach): the root `MetaData` table of (Source, Link,
Destination) strings leading Root → Measurement → Surface → Path, the
surface dataset (rows along y) with its `Unit`, `X/Y/Z Converter` and
`No Data` attributes, and the instrument's serial number and type under
`/Attributes`.

`python datx_layout.py OUT.datx` writes the small file of asperity-io's unit
tests (crates/io/tests/data/small.datx).
"""
import sys

import h5py
import numpy as np


def write_datx(path, heights, dx, dy, unit="NanoMeters", no_data=None, serial=None, system_type=None,
               fixed_strings=False):
    """`heights` (rows = y, columns = x); `dx`, `dy` pixel sizes in metres.
    Strings are variable-length unless `fixed_strings` (each its own width)."""
    def s(text):
        return np.bytes_(text) if fixed_strings else text

    vlen = h5py.string_dtype()
    str_dtype = "S64" if fixed_strings else vlen
    rows = [("Root", "Measurement", "{m-uuid}"), ("{m-uuid}", "Surface", "{s-uuid}"),
            ("{m-uuid}", "Name", "interferometer run"), ("{s-uuid}", "Path", "/Measurement/Surface"),
            ("{s-uuid}", "Kind", "Surface")]
    table = np.array([tuple(s(v) for v in r) for r in rows],
                     dtype=[("Source", str_dtype), ("Link", str_dtype), ("Destination", str_dtype)])
    converter_dtype = np.dtype([("Category", str_dtype), ("BaseUnit", str_dtype),
                                ("Parameters", h5py.vlen_dtype(np.float64))])

    def converter(category, base, parameters):
        c = np.empty(1, dtype=converter_dtype)
        c[0] = (s(category), s(base), np.array(parameters, dtype=np.float64))
        return c

    with h5py.File(path, "w") as h5:
        h5.create_dataset("MetaData", data=table)
        d = h5.create_dataset("Measurement/Surface", data=heights)
        d.attrs["X Converter"] = converter("LateralCat", "Pixels", [0.0, dx, 0.0, 0.0])
        d.attrs["Y Converter"] = converter("LateralCat", "Pixels", [0.0, dy, 0.0, 0.0])
        d.attrs["Z Converter"] = converter("HeightCat", unit, [0.0, 6.328e-7, 0.5, 1.0])
        d.attrs["Unit"] = np.array([s(unit)], dtype=str_dtype)
        if no_data is not None:
            d.attrs["No Data"] = np.array([no_data], dtype=np.float64)
        g = h5.create_group("Attributes/{a-uuid}")
        if serial is not None:
            g.attrs["Data Context.Data Attributes.System Serial Number"] = np.array([s(serial)], dtype=str_dtype)
        if system_type is not None:
            g.attrs["Data Context.Data Attributes.System Type"] = np.array([s(system_type)], dtype=str_dtype)


if __name__ == "__main__":
    z = np.arange(12.0).reshape(3, 4)
    z[1, 2] = np.finfo(np.float64).max
    write_datx(sys.argv[1], z, 0.5e-6, 0.25e-6, no_data=np.finfo(np.float64).max, serial="4242",
               system_type="NewView 9000")
