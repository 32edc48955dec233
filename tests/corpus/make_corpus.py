#!/usr/bin/env python3
"""The hostile-input corpus of issue #20: malformed files and bad parameters.

    python3 tests/corpus/make_corpus.py OUT_DIR [ASPERITY_BINARY]

writes every malformed file into OUT_DIR and OUT_DIR/cases.json, the list of
command lines to run there. Each case must end with exit code 2 and one
`error:` line naming the cause once, without a panic or a signal, leave the
pre-existing output file (`out.EXT`, "precious") unchanged and no temporary
file behind; `crates/cli/tests/corpus.rs` checks exactly that against the real
binary. A case may add "needle", text its error must contain.

Only the standard library is used. Formats that need an encoder (OpenEXR, the
16-bit PNG with asperity's tEXt keys, binary PLY) start from a valid file the
binary writes, which is then damaged in ways no reader may accept. Everything
is deterministic: the same files every run.
"""

import binascii
import json
import os
import struct
import subprocess
import sys
import zlib

OUT = sys.argv[1]
BIN = sys.argv[2] if len(sys.argv) > 2 else None
os.makedirs(OUT, exist_ok=True)

FILES = []  # (name, bytes)
CASES = []  # {"name", "args", "output", "needle"?}


def file(name, data):
    if isinstance(data, str):
        data = data.encode("utf-8")
    FILES.append((name, data))
    return name


def case(name, args, output="out.ply", needle=None):
    c = {"name": name, "args": args, "output": output}
    if needle:
        c["needle"] = needle
    CASES.append(c)


# ---------------------------------------------------------------- meshes ----
OCT_V = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
OCT_F = "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n"

OBJ_BAD = {
    "obj_index_zero": OCT_V + "f 0 1 2\n",
    "obj_index_past_end": OCT_V + "f 1 2 99\n",
    "obj_negative_past_start": OCT_V + "f -1 -2 -99\n",
    "obj_face_two_corners": OCT_V + OCT_F + "f 1 2\n",
    "obj_face_one_corner": OCT_V + "f 1\n",
    "obj_face_no_corner": OCT_V + "f\n",
    "obj_vertex_nan": "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "obj_vertex_inf": "v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "obj_vertex_two_coords": "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "obj_vertex_word": "v zero 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "obj_no_face": OCT_V,
    "obj_empty": "",
    "obj_binary_garbage": bytes(range(256)) * 4,
    "obj_index_word": OCT_V + "f a b c\n",
    "obj_huge_index": OCT_V + "f 1 2 99999999999999999999\n",
    "obj_texture_only_index": OCT_V + "f /1 /2 /3\n",
    "obj_relative_normal_before_start": OCT_V + "vn 0 0 1\nf 1//-5 2//1 3//1\n",
    "obj_index_beyond_listed": "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n",
}
for name, text in OBJ_BAD.items():
    f = file(name + ".obj", text)
    case(name + "_info", ["info", f], output="out.txt")
for name in ["obj_index_zero", "obj_face_two_corners", "obj_vertex_nan", "obj_no_face"]:
    case(name + "_subdiv", ["subdiv", "--base", name + ".obj", "-o", "out.ply"])
    case(name + "_surface_ca", ["surface-ca", name + ".obj", "--cells", "500", "-o", "out.ply"])

# Geometry every surface method refuses the same way.
GEOMETRY_BAD = {
    "bowtie": ("v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n",
               "non-manifold vertex"),
    "fin": ("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
            "non-manifold edge"),
    "flipped": ("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nf 1 2 3\nf 1 2 4\n",
                "inconsistent orientation"),
    "sliver": ("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "degenerate"),
}
for name, (text, needle) in GEOMETRY_BAD.items():
    f = file(name + ".obj", text)
    case(name + "_subdiv", ["subdiv", "--base", f, "-o", "out.ply"], needle=needle)
    case(name + "_surface_ca", ["surface-ca", f, "--cells", "500", "-o", "out.ply"], needle=needle)
    case(name + "_growth_mesh", ["growth", "bd", "--substrate", "mesh", "--mesh", f,
                                 "--layers", "1", "-o", "out.ply"], needle=needle)

PLY_HEAD = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
PLY_FACE = "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
PLY_BAD = {
    "ply_no_magic": "format ascii 1.0\nend_header\n",
    "ply_no_end_header": PLY_HEAD + "element face 1\n",
    "ply_bad_format": "ply\nformat ebcdic 1.0\nend_header\n",
    "ply_truncated_vertices": PLY_HEAD + PLY_FACE + "0 0 0\n1 0 0\n",
    "ply_truncated_faces": PLY_HEAD + PLY_FACE + "0 0 0\n1 0 0\n0 1 0\n",
    "ply_index_past_end": PLY_HEAD + PLY_FACE + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
    "ply_face_two_corners": PLY_HEAD + PLY_FACE + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
    "ply_nan_vertex": PLY_HEAD + PLY_FACE + "nan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    "ply_word_in_data": PLY_HEAD + PLY_FACE + "0 0 zero\n1 0 0\n0 1 0\n3 0 1 2\n",
    "ply_huge_count": "ply\nformat ascii 1.0\nelement vertex 4294967295\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n",
    "ply_huge_binary_count": "ply\nformat binary_little_endian 1.0\nelement vertex 999999999999\nproperty double x\nproperty double y\nproperty double z\nend_header\n",
    "ply_negative_count": "ply\nformat ascii 1.0\nelement vertex -3\nproperty float x\nend_header\n",
    "ply_list_float_count": PLY_HEAD + "element face 1\nproperty list float int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    "ply_unknown_type": "ply\nformat ascii 1.0\nelement vertex 1\nproperty quaternion x\nend_header\n1\n",
    "ply_no_x": "ply\nformat ascii 1.0\nelement vertex 1\nproperty float q\nend_header\n1\n",
    "ply_empty": "",
    "ply_list_past_data": PLY_HEAD + PLY_FACE + "0 0 0\n1 0 0\n0 1 0\n255 0 1 2\n",
}
for name, text in PLY_BAD.items():
    f = file(name + ".ply", text)
    case(name + "_info", ["info", f], output="out.txt")
for name in ["ply_index_past_end", "ply_huge_count", "ply_nan_vertex"]:
    case(name + "_convert", ["convert", name + ".ply", "out.obj"], output="out.obj")
    case(name + "_reconstruct", ["reconstruct", name + ".ply", "-o", "out.ply"])

STL_TRI = struct.pack("<12f", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0) + b"\0\0"
STL_BAD = {
    "stl_count_past_data": b"\0" * 80 + struct.pack("<I", 1000) + STL_TRI,
    "stl_huge_count": b"\0" * 80 + struct.pack("<I", 0xFFFFFFFF) + STL_TRI,
    "stl_short_header": b"\0" * 40,
    "stl_nan": b"\0" * 80 + struct.pack("<I", 1) + struct.pack("<12f", 0, 0, 1, float("nan"), 0, 0, 1, 0, 0, 0, 1, 0) + b"\0\0",
    "stl_no_triangle": b"\0" * 80 + struct.pack("<I", 0),
    "stl_ascii_missing_vertex": "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid t\n",
    "stl_ascii_word": "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
    "stl_ascii_unterminated": "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n",
}
for name, data in STL_BAD.items():
    f = file(name + ".stl", data)
    case(name + "_render", ["render", f, "-o", "out.png"], output="out.png")
case("stl_repeated_corner_subdiv", ["subdiv", "--base", file("stl_repeated_corner.stl",
     b"\0" * 80 + struct.pack("<I", 1) + struct.pack("<12f", 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0) + b"\0\0"),
     "-o", "out.ply"])


# --------------------------------------------------------- height fields ----
def npy(descr, shape, payload, version=b"\x01\x00", fortran="False", magic=b"\x93NUMPY"):
    h = "{'descr': '%s', 'fortran_order': %s, 'shape': %s, }" % (descr, fortran, shape)
    h += " " * (63 - (10 + len(h)) % 64) + "\n"
    return magic + version + struct.pack("<H", len(h)) + h.encode("latin-1") + payload


NPY_BAD = {
    "npy_bad_magic": npy("<f8", "(2, 2)", b"\0" * 32, magic=b"\x93NUMPZ"),
    "npy_truncated": npy("<f8", "(4, 4)", b"\0" * 64),
    "npy_huge_shape": npy("<f8", "(4294967296, 4294967296)", b"\0" * 64),
    "npy_overflow_shape": npy("<f8", "(18446744073709551615, 3)", b"\0" * 64),
    "npy_complex": npy("<c16", "(2, 2)", b"\0" * 64),
    "npy_object": npy("|O", "(2, 2)", b"\0" * 64),
    "npy_three_dims": npy("<f8", "(2, 2, 2)", b"\0" * 64),
    "npy_empty_shape": npy("<f8", "(0, 0)", b""),
    # NaN is a missing point (issue #38); infinity is never a height.
    "npy_inf": npy("<f8", "(1, 2)", struct.pack("<2d", 1.0, float("inf"))),
    "npy_all_missing": npy("<f8", "(2, 2)", struct.pack("<4d", *[float("nan")] * 4)),
    "npy_bad_version": npy("<f8", "(1, 1)", b"\0" * 8, version=b"\x09\x00"),
    "npy_header_past_end": b"\x93NUMPY\x01\x00\xff\xff{'descr': '<f8'",
    "npy_no_shape": b"\x93NUMPY\x01\x00" + struct.pack("<H", 46) + b"{'descr': '<f8', 'fortran_order': False, }   \n",
    "npy_non_ascii_dtype": npy("<\u00e9", "(1, 1)", b"\0" * 8),
    "npy_empty_profile": npy("<f8", "(0,)", b""),
}
for name, data in NPY_BAD.items():
    f = file(name + ".npy", data)
    case(name + "_analyze", ["analyze", f], output="out.txt")
for name in ["npy_truncated", "npy_huge_shape", "npy_inf", "npy_all_missing"]:
    case(name + "_render", ["render", name + ".npy", "-o", "out.png"], output="out.png")
    case(name + "_facet", ["facet", name + ".npy", "-o", "out.ply"])


def png_chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", binascii.crc32(kind + data) & 0xFFFFFFFF)


def png(width, height, depth=16, color=0, text=(), rows=None, crc_ok=True, idat=True):
    sig = b"\x89PNG\r\n\x1a\n"
    ihdr = png_chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, depth, color, 0, 0, 0))
    body = b"".join(png_chunk(b"tEXt", k.encode() + b"\0" + v.encode()) for k, v in text)
    if rows is None:
        bpp = depth // 8 if depth >= 8 else 1
        rows = b"".join(b"\0" + b"\0" * (width * bpp) for _ in range(min(height, 4)))
    data = png_chunk(b"IDAT", zlib.compress(rows)) if idat else b""
    if not crc_ok:
        data = data[:-4] + b"\0\0\0\0"
    return sig + ihdr + body + data + png_chunk(b"IEND", b"")


PNG_BAD = {
    "png_bomb": png(100000, 100000),
    "png_zero_width": png(0, 4),
    "png_bad_crc": png(4, 4, crc_ok=False),
    "png_no_idat": png(4, 4, idat=False),
    "png_truncated_rows": png(64, 64, rows=b"\0" * 10),
    "png_inverted_range": png(2, 2, text=[("asperity:z_min", "5"), ("asperity:z_max", "1")]),
    "png_nan_range": png(2, 2, text=[("asperity:z_min", "nan"), ("asperity:z_max", "1")]),
    "png_zero_spacing": png(2, 2, text=[("asperity:dx", "0"), ("asperity:dy", "1")]),
    "png_half_spacing": png(2, 2, text=[("asperity:dx", "1")]),
    "png_not_png": b"GIF89a" + b"\0" * 64,
    "png_signature_only": b"\x89PNG\r\n\x1a\n",
}
for name, data in PNG_BAD.items():
    f = file(name + ".png", data)
    case(name + "_info", ["info", f], output="out.txt")
case("png_bomb_dla_image", ["growth", "dla", "--seed-shape", "image", "--image", "png_bomb.png",
                            "--size", "32x32x16", "-o", "out.ply"], needle="memory limit")
case("png_bomb_ca_init", ["ca", "run", "--rule", "450", "--steps", "2", "--init", "png_bomb.png",
                          "-o", "out.npy"], output="out.npy", needle="memory limit")
case("png_bomb_convert", ["--max-memory", "64M", "convert", "png_bomb.png", "out.npy"],
     output="out.npy", needle="memory limit")


def gsf(fields, data=b"", pad=True):
    text = "Gwyddion Simple Field 1.0\n" + "".join("%s = %s\n" % kv for kv in fields)
    raw = text.encode()
    if pad:
        raw += b"\0" * (4 - len(raw) % 4)
    return raw + data


GSF_BAD = {
    "gsf_no_magic": b"Gwyddion Complex Field 1.0\nXRes = 2\nYRes = 2\n\0\0" + b"\0" * 16,
    "gsf_zero_xres": gsf([("XRes", "0"), ("YRes", "2")]),
    "gsf_negative_xreal": gsf([("XRes", "2"), ("YRes", "2"), ("XReal", "-1")], struct.pack("<4f", 0, 1, 2, 3)),
    "gsf_zero_yreal": gsf([("XRes", "2"), ("YRes", "2"), ("YReal", "0")], struct.pack("<4f", 0, 1, 2, 3)),
    "gsf_truncated": gsf([("XRes", "4"), ("YRes", "4")], struct.pack("<4f", 0, 1, 2, 3)),
    "gsf_huge": gsf([("XRes", "100000"), ("YRes", "100000")], struct.pack("<4f", 0, 1, 2, 3)),
    "gsf_inf": gsf([("XRes", "2"), ("YRes", "1")], struct.pack("<2f", 0, float("inf"))),
    "gsf_words": gsf([("XRes", "two"), ("YRes", "2")]),
    "gsf_no_padding": gsf([("XRes", "1"), ("YRes", "1")], b"", pad=False),
}
for name, data in GSF_BAD.items():
    f = file(name + ".gsf", data)
    case(name + "_info", ["info", f], output="out.txt")

CSV_BAD = {
    "csv_ragged": "1,2,3\n4,5\n",
    "csv_word": "1,2\n3,x\n",
    "csv_inf": "1,2\n3,inf\n",
    "csv_empty": "",
    "csv_only_comments": "# nothing here\n",
    "csv_bad_geometry": "# asperity dx=-1 dy=1 x0=0 y0=0\n1,2\n3,4\n",
}
for name, text in CSV_BAD.items():
    f = file(name + ".csv", text)
    case(name + "_analyze", ["analyze", f], output="out.txt")

XYZ_BAD = {
    "xyz_two_columns": "0 0\n1 1\n",
    "xyz_word": "0 0 zero\n",
    "xyz_nan": "0 0 nan\n1 1 1\n",
    "xyz_empty": "",
}
for name, text in XYZ_BAD.items():
    f = file(name + ".xyz", text)
    case(name + "_reconstruct", ["reconstruct", f, "-o", "out.ply"])
case("xyz_identical_reconstruct", ["reconstruct", file("xyz_identical.xyz", "1 1 1\n1 1 1\n1 1 1\n"), "-o", "out.ply"],
     needle="identical")

# -------------------------------------------------- texts of the methods ----
SCENES = {
    "scene_not_toml": "this is = = not toml [",
    "scene_unknown_key": "[base]\nshape = \"cube\"\nfrobnicate = 3\n",
    "scene_unknown_shape": "[base]\nshape = \"klein-bottle\"\n",
    "scene_too_many_levels": "[base]\nshape = \"cube\"\nlevels = 60\n",
    "scene_unknown_detail": "[base]\nshape = \"cube\"\n[[detail]]\nkind = \"fur\"\n",
    "scene_nan": "[base]\nshape = \"cube\"\n[[detail]]\nkind = \"rock\"\namplitude = nan\n",
}
for name, text in SCENES.items():
    case(name, ["subdiv", file(name + ".toml", text), "-o", "out.ply"])

IFS = {
    "ifs_not_json": "{ operators: ",
    "ifs_empty_object": "{}",
    "ifs_not_barycentric": json.dumps({"name": "x", "curve": {"operators": [[[1, 0], [0, 1]], [[0.5, 0.5], [0.5, 0.5]]], "control": [[0, 0], [1, 0]]}}),
    "ifs_wrong_shape": json.dumps({"name": "x", "curve": {"operators": [[[1, 0, 0]], [[1]]], "control": [[0, 0]]}}),
    "ifs_nan": '{"name": "x", "curve": {"operators": [[[NaN, 0], [0, 1]]], "control": [[0, 0], [1, 0]]}}',
}
for name, text in IFS.items():
    case(name, ["ifs", "surface", "--ifs", file(name + ".json", text), "-o", "out.ply"])

case("profile_word", ["subdiv", "--base", "revolution:" + file("profile_word.txt", "0.5 zero\n"), "-o", "out.ply"])
case("profile_one_row", ["subdiv", "--base", "revolution:" + file("profile_one_row.txt", "0.5 0\n"), "-o", "out.ply"])
case("details_not_json", ["subdiv", "--base", "cube", "--apply-details", file("details_bad.json", "[1, 2"), "-o", "out.ply"])
case("sites_word", ["surface-ca", "builtin:cube", "--cells", "500", "--site-points", file("sites_word.xyz", "a b c\n"), "-o", "out.ply"])
case("polyline_word", ["facet", "h.npy", "--polyline", file("polyline_word.csv", "0,0\n1,x\n"), "-o", "out.ply"])
case("interpolate_word", ["interpolate", "h.npy", "--points", file("points_word.csv", "x,y\n"), "-o", "out.csv"], output="out.csv")

# Unknown or unreadable files and folders.
case("missing_file", ["info", "nosuch.ply"], output="out.txt", needle="nosuch.ply")
case("unknown_extension", ["info", file("mystery.doc", "hello")], output="out.txt", needle="unknown file type")
case("directory_as_input", ["info", "."], output="out.txt")
case("output_in_missing_folder", ["generate", "fbm", "--size", "8", "-o", "nosuch/out.npy"], output="out.npy",
     needle="the folder does not exist")
case("glb_as_input", ["info", file("model.glb", b"glTF\x02\0\0\0")], output="out.txt", needle="write-only")

# ------------------------------------------------------- bad parameters ----
H = ["h.npy"]
PARAMS = [
    ("fbm_size_zero", ["generate", "fbm", "--size", "0", "-o", "out.npy"], "out.npy"),
    ("fbm_size_overflow", ["generate", "fbm", "--size", "4294967296", "-o", "out.npy"], "out.npy"),
    ("fbm_size_max", ["generate", "fbm", "--size", "18446744073709551615", "-o", "out.npy"], "out.npy"),
    ("fbm_hurst_big", ["generate", "fbm", "--hurst", "1.5", "-o", "out.npy"], "out.npy"),
    ("fbm_hurst_nan", ["generate", "fbm", "--hurst", "nan", "-o", "out.npy"], "out.npy"),
    ("fbm_rms_negative", ["generate", "fbm", "--rms=-1", "-o", "out.npy"], "out.npy"),
    ("fbm_no_output", ["generate", "fbm"], "out.npy"),
    ("fbm_unknown_format", ["generate", "fbm", "--size", "8", "-o", "out.doc"], "out.doc"),
    ("rdsr_size_one", ["growth", "rdsr", "--size", "1", "-o", "out.npy"], "out.npy"),
    ("rdsr_dim_three", ["growth", "rdsr", "--dim", "3", "-o", "out.npy"], "out.npy"),
    ("rdsr_layers_negative", ["growth", "rdsr", "--layers=-1", "-o", "out.npy"], "out.npy"),
    ("rdsr_layers_nan", ["growth", "rdsr", "--layers", "nan", "-o", "out.npy"], "out.npy"),
    ("rdsr_runs_zero", ["growth", "rdsr", "--runs", "0", "-o", "out.npy"], "out.npy"),
    ("rdsr_runs_years", ["growth", "rdsr", "--runs", "1000000000", "-o", "out.npy"], "out.npy"),
    ("rdsr_bin_not_divisor", ["growth", "rdsr", "--size", "32", "--bin", "3", "-o", "out.npy"], "out.npy"),
    ("rdsr_alpha_two_sizes", ["growth", "rdsr", "--size", "16", "--layers", "2", "--alpha-sizes", "0,1", "-o", "out.npy"], "out.npy"),
    ("rdsr_alpha_huge", ["--max-memory", "1G", "growth", "rdsr", "--size", "16", "--layers", "2", "--alpha-sizes", "30000,20000,10000", "-o", "out.npy"], "out.npy"),
    ("rdsr_fit_window_reversed", ["growth", "rdsr", "--size", "16", "--fit-window", "5,2", "-o", "out.npy"], "out.npy"),
    ("rdsr_samples_zero", ["growth", "rdsr", "--size", "16", "--samples-per-decade", "0", "-o", "out.npy"], "out.npy"),
    ("dla_particles_zero", ["growth", "dla", "--particles", "0", "-o", "out.ply"], "out.ply"),
    ("dla_stick_zero", ["growth", "dla", "--stick", "0", "-o", "out.ply"], "out.ply"),
    ("dla_stick_big", ["growth", "dla", "--stick", "1.5", "-o", "out.ply"], "out.ply"),
    ("dla_size_zero", ["growth", "dla", "--size", "0x8x8", "-o", "out.ply"], "out.ply"),
    ("dla_overfull", ["growth", "dla", "--size", "4x4x4", "--particles", "100", "-o", "out.ply"], "out.ply"),
    ("dla_mesh_missing", ["growth", "dla", "--seed-shape", "mesh", "-o", "out.ply"], "out.ply"),
    ("ca_rule_huge", ["ca", "run", "--rule", "99999999999999", "--steps", "2", "-o", "out.npy"], "out.npy"),
    ("ca_size_zero", ["ca", "run", "--rule", "450", "--steps", "2", "--size", "0x5", "--init", "random:0.5", "-o", "out.npy"], "out.npy"),
    ("ca_density_big", ["ca", "run", "--rule", "450", "--steps", "2", "--size", "8x8", "--init", "random:2", "-o", "out.npy"], "out.npy"),
    ("ca_density_word", ["ca", "run", "--rule", "450", "--steps", "2", "--size", "8x8", "--init", "random:abc", "-o", "out.npy"], "out.npy"),
    ("ca_infinite_with_size", ["ca", "run", "--rule", "450", "--steps", "2", "--size", "8x8", "--init", "seed", "--boundary", "infinite", "-o", "out.npy"], "out.npy"),
    ("ca_grid_too_big", ["ca", "run", "--rule", "450", "--steps", "10", "--size", "65536x65536", "--init", "random:0.5", "-o", "out.npy"], "out.npy"),
    ("ca_steps_years", ["ca", "run", "--rule", "450", "--steps", "1000000", "--init", "seed", "-o", "out.npy"], "out.npy"),
    ("ca_gallery_tile_zero", ["ca", "gallery", "--tile", "0x0", "-o", "out.png"], "out.png"),
    ("ca_gallery_tile_huge", ["ca", "gallery", "--tile", "100000x100000", "-o", "out.png"], "out.png"),
    ("render_fov_zero", ["render"] + H + ["--fov", "0", "-o", "out.png"], "out.png"),
    ("render_fov_nan", ["render"] + H + ["--fov", "nan", "-o", "out.png"], "out.png"),
    ("render_eye_is_target", ["render"] + H + ["--eye", "1,1,1", "--target", "1,1,1", "-o", "out.png"], "out.png"),
    ("render_scalar_unknown", ["render"] + H + ["--scalar", "nosuch", "--shader", "curvature", "-o", "out.png"], "out.png"),
    ("render_size_zero", ["render"] + H + ["--size", "0x0", "-o", "out.png"], "out.png"),
    ("render_supersample_zero", ["render"] + H + ["--supersample", "0", "-o", "out.png"], "out.png"),
    ("render_turntable_many", ["render"] + H + ["--turntable", "4000000", "-o", "out.png"], "out.png"),
    ("reconstruct_resolution_zero", ["reconstruct", "pts.xyz", "--resolution", "0", "-o", "out.ply"], "out.ply"),
    ("reconstruct_offset_negative", ["reconstruct", "pts.xyz", "--offset=-1", "-o", "out.ply"], "out.ply"),
    ("reconstruct_iterations_huge", ["reconstruct", "pts.xyz", "--iterations", "1000000000", "-o", "out.ply"], "out.ply"),
    ("reconstruct_save_every_zero", ["reconstruct", "pts.xyz", "--save-every", "0", "-o", "out.ply"], "out.ply"),
    ("ifs_preset_unknown", ["ifs", "surface", "--preset", "nosuch", "-o", "out.ply"], "out.ply"),
    ("ifs_depth_huge", ["ifs", "surface", "--preset", "takagi-landsberg-surface", "--depth", "100", "-o", "out.ply"], "out.ply"),
    ("ifs_w_big", ["ifs", "surface", "--preset", "takagi-landsberg", "--w", "2", "-o", "out.ply"], "out.ply"),
    ("surfca_sites_zero", ["surface-ca", "builtin:cube", "--cells", "500", "--sites", "0", "-o", "out.ply"], "out.ply"),
    ("surfca_cells_zero", ["surface-ca", "builtin:cube", "--cells", "0", "-o", "out.ply"], "out.ply"),
    ("surfca_diagonal_big", ["surface-ca", "builtin:cube", "--cells", "500", "--diagonal-p", "2", "-o", "out.ply"], "out.ply"),
    ("surfca_frames_zero", ["surface-ca", "builtin:cube", "--cells", "500", "--frames", "0", "-o", "out.ply"], "out.ply"),
    ("surfca_displace_nan", ["surface-ca", "builtin:cube", "--cells", "500", "--app", "corrosion", "--steps", "2", "--displace", "nan", "-o", "out.ply"], "out.ply"),
    ("surfca_k1_negative", ["surface-ca", "builtin:cube", "--cells", "500", "--app", "corrosion", "--k1=-1", "-o", "out.ply"], "out.ply"),
    ("surfca_steps_years", ["surface-ca", "builtin:cube", "--cells", "500", "--app", "corrosion", "--steps", "18446744073709551615", "-o", "out.ply"], "out.ply"),
    ("surfca_builtin_unknown", ["surface-ca", "builtin:teapot", "-o", "out.ply"], "out.ply"),
    ("subdiv_levels_huge", ["subdiv", "--base", "cube", "--levels", "40", "-o", "out.ply"], "out.ply"),
    ("subdiv_base_unknown", ["subdiv", "--base", "klein", "-o", "out.ply"], "out.ply"),
    ("subdiv_detail_unknown", ["subdiv", "--base", "cube", "--detail", "fur", "-o", "out.ply"], "out.ply"),
    ("subdiv_crease_not_edge", ["subdiv", "--base", "cube", "--crease", "0-99:1", "-o", "out.ply"], "out.ply"),
    ("subdiv_frames_many", ["subdiv", "--base", "cube", "--frames", "4000000", "-o", "out.ply"], "out.ply"),
    ("analyze_fit_window_empty", ["analyze"] + H + ["--fit-window", "0,0"], "out.txt"),
    ("convert_points_to_stl", ["convert"] + H + ["out.stl", "--as", "points"], "out.stl"),
    ("convert_repair_height", ["convert"] + H + ["out.npy", "--repair"], "out.npy"),
    ("max_memory_zero", ["--max-memory", "0", "generate", "fbm", "-o", "out.npy"], "out.npy"),
    ("max_memory_word", ["--max-memory", "lots", "generate", "fbm", "-o", "out.npy"], "out.npy"),
    ("max_time_word", ["--max-time", "soon", "generate", "fbm", "-o", "out.npy"], "out.npy"),
    ("threads_zero", ["--threads", "0", "generate", "fbm", "-o", "out.npy"], "out.npy"),
    ("stdout_without_format", ["generate", "fbm", "-o", "-"], "out.npy"),
    ("unknown_command", ["frobnicate"], "out.txt"),
]
for name, args, output in PARAMS:
    case("param_" + name, args, output=output)

# ------------------------------------------------------------ write out ----
for name, data in FILES:
    with open(os.path.join(OUT, name), "wb") as fh:
        fh.write(data)
# Good inputs some parameter cases need.
with open(os.path.join(OUT, "pts.xyz"), "w") as fh:
    fh.write("".join("%d %d %d\n" % (i % 3, (i // 3) % 3, i // 9) for i in range(27)))
if BIN:
    subprocess.run([BIN, "--quiet", "generate", "fbm", "--size", "16", "-o", "h.npy"], cwd=OUT, check=True)
with open(os.path.join(OUT, "cases.json"), "w") as fh:
    json.dump(CASES, fh, indent=1)
n_files = len(FILES)
print("%d malformed files, %d cases (%d bad parameter sets)" % (n_files, len(CASES), len(PARAMS)))
