#!/usr/bin/env bash
# Writes the seed inputs of every fuzzed reader into fuzz/seeds/NAME/ with the
# asperity binary (small valid files of every flavour each reader accepts).
# Usage: fuzz/make_seeds.sh [ASPERITY_BINARY]   (default: target/release/asperity)
set -euo pipefail
cd "$(dirname "$0")/.."
A=$(realpath "${1:-target/release/asperity}")
S=fuzz/seeds
rm -rf "$S"
mkdir -p "$S"/{ply,obj,stl,npy,png,exr,gsf,csv,gwy,x3p,sdf,sur,tmd,plu,nid,mi,ibw,park,hfm,dektak,csvlinescan,nms,mat,npz,hgt,vk,mdt,os3d,datx,oir,poir,zmg,plux,zon,lext,jpk,qep,nmm,opdx,mnt,asc,mitutoyo,h5,nc,di,frt,opd,bcr,metropro,al3d,wsxm,xyz,xy,scene_toml,ifs_json,detail_json,profile,alpha_map}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
q() { "$A" --quiet "$@"; }
q generate fbm --size 8 --seed 1 -o "$T/h.npy"
for f in gsf csv png exr; do q convert "$T/h.npy" "$S/$f/h8.$f"; done
q convert "$T/h.npy" "$S/gwy/asperity.gwy"
q --xy-unit um --z-unit nm convert "$T/h.npy" "$S/x3p/asperity.x3p"
# Files other programs wrote, where they are installed (.ci/run installs both).
if command -v gwyddion >/dev/null; then gwyddion --convert-to-gwy="$S/gwy/gwyddion.gwy" "$S/gsf/h8.gsf"; fi
if python3 -c "import x3pio" 2>/dev/null; then
  python3 -c "import sys, numpy as np, x3pio; x3pio.write(sys.argv[1], np.arange(20.).reshape(4, 5) * 1e-9, x_scale=1e-6, y_scale=1e-6, z_type=x3pio.DataType.INT16)" "$S/x3p/x3pio_int16.x3p"
fi
# MATLAB files as scipy writes them (plain and compressed; a string and a
# complex matrix beside the channels).
if python3 -c "import scipy.io" 2>/dev/null; then
  python3 -c "import sys, numpy as np, scipy.io
v = {'z': np.arange(12.0).reshape(3, 4), 'n': np.arange(6, dtype=np.int16).reshape(2, 3), 's': 'text', 'c': np.ones((2, 2)) * (1 + 1j)}
scipy.io.savemat(sys.argv[1] + '/plain.mat', v)
scipy.io.savemat(sys.argv[1] + '/compressed.mat', v, do_compression=True)" "$S/mat"
fi
# JPK image scans (TIFF pages with JPK's private tags), where numpy is installed.
if python3 -c "import numpy" 2>/dev/null; then
  python3 fuzz/jpk_seed.py "$S/jpk" && cp "$S/jpk/r0.jpk" crates/io/tests/data/small.jpk
fi
python3 -c "import sys, numpy as np
np.savez(sys.argv[1] + '/savez.npz', z=np.arange(12.0).reshape(3, 4), v=np.arange(3))
np.savez_compressed(sys.argv[1] + '/compressed.npz', z=np.arange(6, dtype=np.int16).reshape(2, 3))" "$S/npz"
# SDF: asperity's text file, the standard's example, a binary int16 file;
# Digital Surf: a 4 × 3 int16 surface with the special-points flag; TrueMap 3 × 2.
q --xy-unit um --z-unit nm convert "$T/h.npy" "$S/sdf/asperity.sdf"
cp tests/data/surfacetopography/sdf-1.sdf "$S/sdf/"
python3 - "$S" <<'PY'
import struct, sys
s = sys.argv[1]
head = b"bISO-1.0" + b"asperity".ljust(10, b"\0") + b"0" * 24 + struct.pack("<HHddddbbb", 3, 2, 1e-6, 1e-6, 1e-9, 1e-9, 0, 5, 0)
open(f"{s}/sdf/binary_int16.sdf", "wb").write(head + struct.pack("<6h", 1, -2, 3, -32768 + 1, 5, 6))
h = bytearray(512)
h[0:12] = b"DIGITAL SURF"
struct.pack_into("<HHHH", h, 12, 1, 1, 1, 1)
struct.pack_into("<H", h, 86, 1)
struct.pack_into("<Hiiiii", h, 98, 16, -5, 40, 4, 3, 12)
struct.pack_into("<fff", h, 120, 0.5, 0.5, 0.01)
for k, unit in enumerate([b"um", b"um", b"nm"]):
    h[180 + 16 * k:180 + 16 * k + 2] = unit
open(f"{s}/sur/s4x3.sur", "wb").write(bytes(h) + struct.pack("<12h", *range(-5, 7)))
t = b"Binary TrueMap Data File v2.0\r\n\0" + b"Created by TrueMap v6\r\n\0"
b = "fileformat = bcrf_unicode\nheadersize = 2048\nxpixels = 3\nypixels = 2\nxlength = 3\nylength = 2\nzunit = um\n"
open(f"{s}/bcr/b3x2.bcrf", "wb").write(b.encode("utf-16-le").ljust(4096, b"\0") + struct.pack("<6f", 1, 2, 3, 4, 5, 6))
m = bytearray(834)
m[0:4] = b"\x88\x1b\x03\x6f"
struct.pack_into(">I", m, 6, 834)
struct.pack_into(">HHH", m, 52, 1, 1, 2)
struct.pack_into(">HH", m, 68, 3, 2)
struct.pack_into(">ff", m, 164, 0.5, 6.4e-7)
struct.pack_into(">f", m, 176, 1.0)
struct.pack_into(">f", m, 184, 1e-6)
struct.pack_into(">h", m, 218, 1)
open(f"{s}/metropro/m3x2.dat", "wb").write(bytes(m) + b"\0" * 4 + struct.pack(">6i", 0, 1, 2, -3, 4, 5))
def tag(k, v):
    return k.encode().ljust(20, b"\0") + v.encode().ljust(30, b"\0") + b"\r\n"
a = b"AliconaImaging\0\r\n"
off = len(a) + 8 * 52 + 256
tags = [("Version", "1"), ("TagCount", "6"), ("Cols", "3"), ("Rows", "2"), ("PixelSizeXMeter", "5e-7"),
        ("PixelSizeYMeter", "5e-7"), ("DepthImageOffset", str(off)), ("InvalidPixelValue", "3e15")]
a += b"".join(tag(k, v) for k, v in tags) + b"\0" * 256
a += (struct.pack("<3f", 1e-6, 2e-6, 3e-6) + b"\0" * 4) * 2
open(f"{s}/al3d/a3x2.al3d", "wb").write(a)
w = ("[Control]\n    X Amplitude: 600 nm\n\n[General Info]\n    Image Data Type: short\n"
     "    Number of columns: 3\n    Number of rows: 2\n    Z Amplitude: 10 nm\n\n"
     "[Miscellaneous]\n    Maximum: 5\n    Minimum: 0\n\n[Header end]\n").encode()
lead = lambda n: f"WSxM file copyright UAM\r\nSxM Image file\r\nImage header size: {n}\r\n".encode()
n = len(lead(0)) + len(w)
n = len(lead(n)) + len(w)
open(f"{s}/wsxm/w3x2.top", "wb").write(lead(n) + w + struct.pack("<6h", 0, 1, 2, 3, 4, 5))
p = bytearray(500)
struct.pack_into("<II", p, 388, 2, 3)
struct.pack_into("<ff", p, 404, 0.5, 0.25)
struct.pack_into("<I", p, 428, 3)
p[489] = 1
open(f"{s}/plu/p3x2.plu", "wb").write(bytes(p) + struct.pack("<II", 2, 3) + struct.pack("<6f", 1, 2, 3, 1000001, 5, 6) + b"\0" * 8)
def opd_entry(name, n):
    return name.encode().ljust(16, b"\0") + struct.pack("<hlH", 0, n, 0)
raw = struct.pack("<HHH", 2, 3, 2) + struct.pack("<6h", 0, 1, 2, 3, 32767, 5)
blocks = [("RAW DATA", raw), ("Wavelength", struct.pack("<f", 600)), ("Mult", struct.pack("<H", 2)),
          ("Pixel_size", struct.pack("<f", 0.5)), ("Aspect", struct.pack("<f", 1))]
o = b"\0\0" + opd_entry("Directory", 24 * (len(blocks) + 1))
o += b"".join(opd_entry(n, len(b)) for n, b in blocks) + b"".join(b for _, b in blocks)
open(f"{s}/opd/o2x3.opd", "wb").write(o)
def frt_block(i, b):
    return struct.pack("<HI", i, len(b)) + b
f = b"FRTM_GLIDERV1.00" + struct.pack("<H", 4)
f += frt_block(0x66, struct.pack("<3I", 3, 2, 32)) + frt_block(0x67, struct.pack("<5dI", 6e-6, 1e-6, 0, 0, 1, 0))
f += frt_block(0x6C, struct.pack("<Id", 7, 1e-9)) + frt_block(0x0B, struct.pack("<6i", 0, 2, 1, -4, 5, 6))
open(f"{s}/frt/f3x2.frt", "wb").write(f)
image = ("\\*Ciao image list\r\n\\Data offset: {}\r\n\\Data length: 12\r\n\\Bytes/pixel: 2\r\n"
         "\\Samps/line: 3\r\n\\Number of lines: 2\r\n\\Scan Size: 3 1 um\r\n"
         "\\@2:Image Data: S [Height] \"Height\"\r\n\\@2:Z scale: V [Sens. Zsens] (0.005 V/LSB) 6.5536 V\r\n")
d = ("\\*File list\r\n\\Version: 0x07200000\r\n\\*Scanner list\r\n\\@Sens. Zsens: V 20 nm/V\r\n"
     + image.format(600) + "\\*File list end\r\n").encode().ljust(600, b"\0")
open(f"{s}/di/d3x2.spm", "wb").write(d + struct.pack("<6h", 0, 1, 2, 3, 4, -5))
import shutil
shutil.copy("tests/data/surfacetopography/nc-1.nc", f"{s}/nc/nc-1.nc")
shutil.copy("tests/data/surfacetopography/opdx-3.opdx", f"{s}/opdx/opdx-3.opdx")
shutil.copy("crates/io/tests/data/small.h5", f"{s}/h5/small.h5")  # written by h5py
shutil.copy("crates/io/tests/data/small.datx", f"{s}/datx/small.datx")  # python/tests/reference/datx_layout.py
shutil.copy("crates/io/tests/data/small.oir", f"{s}/oir/small.oir")  # python/tests/reference/oir_layout.py
import zipfile
with zipfile.ZipFile(f"{s}/poir/small.poir", "w", zipfile.ZIP_DEFLATED) as z:
    z.writestr("manifest.xml", "<manifest/>")
    z.write("crates/io/tests/data/small.oir", "first.oir")
for name in ["gwyddion-export-german.txt", "xy-5.txt", "matrix-6.txt"]:
    shutil.copy(f"tests/data/surfacetopography/{name}", f"{s}/asc/{name}")
open(f"{s}/asc/pixel-size.txt", "w").write("h=2 w=4\npixel size=2e-07 m\nheight conversion factor (-> m)=1e-08\n"
                                          "1 2 3 4\n5 6 7 8\n")
shutil.copy("tests/data/surfacetopography/10x10-one_channel_without_name.ibw", f"{s}/ibw/10x10.ibw")
nset = lambda n, u: (f"[{n}]\r\nPoints=3\r\nLines=2\r\nFrame=Scan forward\r\nDim0Range=3e-6\r\nDim0Unit=m\r\n"
                     f"Dim1Range=1e-6\r\nDim1Unit=m\r\nDim2Name=Z\r\nDim2Unit={u}\r\nDim2Range=65536e-9\r\n"
                     "Dim2Min=-32768e-9\r\nSaveMode=Binary\r\nSaveBits=16\r\nSaveSign=Signed\r\nSaveOrder=Intel\r\n")
n = ("[DataSet]\r\nGroupCount=1\r\nGr0-Count=2\r\nGr0-Ch0=A\r\nGr0-Ch1=B\r\n" + nset("A", "N") + nset("B", "m") + "#!").encode()
open(f"{s}/nid/n3x2.nid", "wb").write(n + bytes(12) + struct.pack("<6h", 0, 1, 2, 3, 4, -5))
mline = lambda k, v: f"{k:<14}{v}\n"
m = mline("fileType", "Image") + mline("xPixels", "3") + mline("yPixels", "2") + mline("xLength", "3e-6") + mline("yLength", "1e-6")
for label, unit in [("Topography", "um"), ("Deflection", "V")]:
    m += mline("bufferLabel", label) + mline("bufferRange", "32768") + mline("bufferUnit", unit)
open(f"{s}/mi/m3x2.mi", "wb").write((m + mline("data", "BINARY")).encode() + struct.pack("<12h", *range(12)))
ph = bytearray(284)
struct.pack_into("<II", ph, 100, 3, 2)
struct.pack_into("<dd", ph, 140, 6.0, 1.0)
struct.pack_into("<ddd", ph, 220, 2.0, 1.0, 1.0)
pdata = struct.pack("<6h", 0, 1, 2, 3, 4, -5)
pdir = 8 + 284 + len(pdata)
pt = b"II*\0" + struct.pack("<I", pdir) + bytes(ph) + pdata + struct.pack("<H", 4)
for tag, typ, cnt, val in [(50432, 4, 1, 0x0E031301), (50433, 4, 1, 0x1000001), (50434, 1, len(pdata), 292), (50435, 7, 284, 8)]:
    pt += struct.pack("<HHII", tag, typ, cnt, val)
open(f"{s}/park/p3x2.tiff", "wb").write(pt)
def vk4():  # a 3 × 2 16-bit height image, 500 × 250 pm pixels, 10 pm a count
    cond, image = 84, 84 + 320
    b = bytearray(image)
    b[:12] = b"VK4_\x01\x00\x00\x00\x00\x00\x00\x00"
    struct.pack_into("<I", b, 36, image)
    for f, v in [(1, 2026), (2, 11), (3, 28), (24, 50), (42, 500), (43, 250), (44, 10)]:
        struct.pack_into("<I", b, cond + 4 * f, v)
    return bytes(b + struct.pack("<7I", 3, 2, 16, 0, 12, 0, 0) + bytes(768) + struct.pack("<6H", 0, 1, 2, 3, 4, 65535))
open(f"{s}/vk/v3x2.vk4", "wb").write(vk4())
import io, zipfile
vk6 = io.BytesIO(b"VK6")
vk6.seek(3)
with zipfile.ZipFile(vk6, "a") as z:
    z.writestr("Vk4File", vk4())
open(f"{s}/vk/v3x2.vk6", "wb").write(vk6.getvalue())
def mdt_frame(adc, xy, z, nx, ny, counts):  # a scanned frame, var_size 40
    body = struct.pack("<ffhffhffh", 0.0, 0.5, xy, 0.0, 0.25, xy, 1.0, 2.0, z)
    body += struct.pack("<BBHH", adc, 0, nx, ny) + bytes(4)
    body += struct.pack("<4H", 0, nx, ny, 0) + struct.pack(f"<{len(counts)}h", *counts)
    return struct.pack("<IH", 22 + len(body), 0) + bytes(14) + struct.pack("<H", 40) + body
frames = [mdt_frame(0, -1, -1, 3, 2, [0, 1, 2, 3, 4, 5]), mdt_frame(1, -2, 0, 2, 1, [10, -10])]
open(f"{s}/mdt/m3x2.mdt", "wb").write(b"\x01\xb0\x93\xff" + bytes(8) + struct.pack("<H", len(frames) - 1)
                                     + bytes(19) + b"".join(frames))
# OmniSurf3D (3 × 2, one invalid point) and KLA Zeta (3 × 2 after a comment)
open(f"{s}/os3d/o3x2.os3d", "wb").write(
    b"OmniSurf3D" + struct.pack("<ii", 1, 0) + struct.pack("<I", 7) + b"probe 7" + struct.pack("<I", 10) + b"2026-11-28"
    + struct.pack("<ii4d", 3, 2, 0.5, 0.25, 0.0, 0.0) + struct.pack("<6f", 1, 2, 3, -3.4e38, 5, 6))
z = bytearray(205)
z[:16] = b"Zeta-Instruments"
struct.pack_into("<II", z, 85, 3, 2)
struct.pack_into("<fff", z, 97, 0.5, 0.25, 0.01)
struct.pack_into("<I", z, 117, 4)
z[131:137] = b"recipe"
open(f"{s}/zmg/z3x2.zmg", "wb").write(bytes(z) + b"note" + struct.pack("<6H", 0, 100, 200, 300, 400, 65535))
# Sensofar PLUX: index.xml and one 3 × 2 f32 layer with a NaN point
import zipfile
with zipfile.ZipFile(f"{s}/plux/p3x2.plux", "w") as z:
    z.writestr("index.xml", "<xml><GENERAL><IMAGE_SIZE_X>3</IMAGE_SIZE_X><IMAGE_SIZE_Y>2</IMAGE_SIZE_Y>"
               "<FOV_X>0.5</FOV_X><FOV_Y>0.25</FOV_Y><DATE>28/11/2026</DATE></GENERAL>"
               "<LAYER_0><FILENAME_Z>LAYER_0.raw</FILENAME_Z></LAYER_0>"
               "<INFO><ITEM_0><NAME>Device</NAME><VALUE>S neox</VALUE></ITEM_0></INFO></xml>")
    z.writestr("LAYER_0.raw", struct.pack("<6f", 1, 2, 3, float("nan"), 5, 6))
# Keyence ZON: KPK0, and KPK1 where the zstandard package is installed
import io
def zon(magic, pack):  # 3 × 2 counts in 16-byte rows, one invalid point
    members = {
        "686613b8-27b5-4a29-8ffc-438c2780873e": b"<C><XYCalibration><MeterPerPixel>2e-6</MeterPerPixel></XYCalibration>"
                                                b"<ZCalibration><MeterPerUnit>1e-8</MeterPerUnit></ZCalibration></C>",
        "4cdb0c75-5706-48cc-a9a1-adf395d609ae": struct.pack("<4i", 3, 2, 4, 16) + struct.pack("<8i", 1, 2, 3, 0, 4, 5, 6, 0),
        "9e7ca6dd-0e6a-4d7b-8986-f0a7b773c916": struct.pack("<4i", 3, 2, 1, 4) + bytes([0, 0, 0, 0, 0, 3, 0, 0]),
    }
    out = io.BytesIO(magic + struct.pack("<I", 3) + b"BMP")
    out.seek(0, 2)
    with zipfile.ZipFile(out, "a") as z:
        for name, data in members.items():
            z.writestr(name, pack(data))
    return out.getvalue()
open(f"{s}/zon/z3x2.zon", "wb").write(zon(b"KPK0", lambda d: d))
try:
    import zstandard
    open(f"{s}/zon/z3x2-zstd.zon", "wb").write(zon(b"KPK1", zstandard.ZstdCompressor().compress))
except ImportError:
    pass
# Olympus LEXT: the HEIGHT page (3 × 2 u32), the measurement page and its EXIF directory
measure = ("<TiffTagDescData><HeightInfo><HeightDataPerPixelX>125000</HeightDataPerPixelX>"
    "<HeightDataPerPixelY>125000</HeightDataPerPixelY><HeightDataPerPixelZ>1000</HeightDataPerPixelZ>"
    "<HeightDataUnitX>0</HeightDataUnitX><HeightDataUnitY>0</HeightDataUnitY>"
    "<HeightDataUnitZ>0</HeightDataUnitZ></HeightInfo></TiffTagDescData>\0").encode()
settings = ("<ExifTagDescData><ImageCommonSettingsInfo><MakerCalibrationValueX>4</MakerCalibrationValueX>"
    "<MakerCalibrationValueY>2</MakerCalibrationValueY><MakerCalibrationValueZ>1</MakerCalibrationValueZ>"
    "</ImageCommonSettingsInfo></ExifTagDescData>\0").encode()
lx = bytearray(b"II*\0" + struct.pack("<I", 8))
entry = lambda tag, kind, count, value: struct.pack("<HHII", tag, kind, count, value)
page1, height_txt = 8 + 90, 8 + 90 + 30
pixels, measure_at = height_txt + 7, height_txt + 7 + 24
exif = measure_at + len(measure)
lx += struct.pack("<H", 7) + entry(256, 4, 1, 3) + entry(257, 4, 1, 2) + entry(258, 3, 1, 32) + entry(270, 2, 7, height_txt)
lx += entry(273, 4, 1, pixels) + entry(277, 3, 1, 1) + entry(279, 4, 1, 24) + struct.pack("<I", page1)
lx += struct.pack("<H", 2) + entry(270, 2, len(measure), measure_at) + entry(34665, 4, 1, exif) + struct.pack("<I", 0)
lx += b"HEIGHT\0" + struct.pack("<6I", 0, 1, 2, 3, 4, 5) + measure
lx += struct.pack("<H", 1) + entry(41995, 2, len(settings), exif + 18) + struct.pack("<I", 0) + settings
open(f"{s}/lext/l3x2.lext", "wb").write(bytes(lx))
# Mahr MarWin QEP: a uniform measured profile with an invalid point, a non-uniform reference
def prf(x, z, flags):  # a MarWin [p3dlin] member
    head = bytearray(0xC4)
    head[:8] = b"[p3dlin]"
    struct.pack_into("<i", head, 0x14, len(x))
    note = b">MachineName=MarSurf"
    n = len(x)
    return (bytes(head) + struct.pack("<ii", 1, len(note)) + note + b"[sellsg]" + b"[Trajec]" + bytes(41)
            + struct.pack(f"<{n}d", *x) + bytes(8 * n) + struct.pack(f"<{n}d", *z) + struct.pack(f"<{n}f", *flags))
with zipfile.ZipFile(f"{s}/qep/q3.qep", "w") as zf:
    zf.writestr("Kontur1.prf", prf([0.0, 0.5, 1.0], [1.0, 2.0, 3.0], [0.0, 1.0, 0.0]))
    zf.writestr("qe_contour_reference_profil_001.tmp", prf([0.0, 0.5, 2.0], [0.0] * 3, [0.0] * 3))
# SIOS NMM: a zip of the scan description and two lines
dashes = "------------------------------------------\n"
with zipfile.ZipFile(f"{s}/nmm/n3x2.zip", "w") as z:  # one scan, 2 lines × 3 points, µm field
    z.writestr("s.dsc", f"{dashes}Scan procedure description file\nCreation time : 2026-11-28\n{dashes}"
               "1 Scan field\nNumber of scans : 1\nNumber of lines : 2\nScan line length : 1 [µm]\n"
               "Scan field width : 0.5 [µm]\nDistance beetween points : 0.5 [µm]\n"
               f"Distance beetween lines : 0.5 [µm]\n{dashes}")
    for i in (1, 2):
        z.writestr(f"s_1_{i}.dsc", "head\n0 : d : Lx : 3 : x\n1 : d : -Lz+Az : 3 : z\n")
        z.writestr(f"s_1_{i}.dat", "".join(f"{k * 5e-7} {(k + 3 * i) * 1e-9}\n" for k in range(3)))
open(f"{s}/hgt/t3.hgt", "wb").write(struct.pack(">9h", 100, -5, -32768, 8848, 0, 1, 2, 3, 4))
open(f"{s}/hfm/h3.hfm", "wb").write(b"X;Y;valid\r\n[mm];[um];[1/0]\r\n1.0;5;1\r\n1.5;6;0\r\n2.0;7;1\r\n")
open(f"{s}/dektak/d3.csv", "wb").write(b"Scan Parameters\r\nLength,1.0 um\r\n\r\nScan Data\r\nLateral um,Raw Micrometer,\r\n"
                                      b"0.0,0.5,,\r\n0.5,0.25,,\r\n1.0,0.0,,\r\n")
for name in ["csv-2.csv", "csv-3.csv"]:  # UTF-16 with an index column; UTF-8
    shutil.copy(f"tests/data/surfacetopography/{name}", f"{s}/csvlinescan/{name}")
nh = bytearray(3468)  # a 3 × 2 µsurf area with one unmeasured point
struct.pack_into("<IIiidd", nh, 0, 2, 1, 0, 65535, 1.0, 2.0)
nh[32:41] = b"OM_MS_2.0"
struct.pack_into("<IIdd", nh, 1368, 3, 2, 500.0, 250.0)
struct.pack_into("<i", nh, 1416, 1)
open(f"{s}/nms/n3x2.nms", "wb").write(bytes(nh) + struct.pack("<6H", 0, 1, 2, 3, 4, 65535) + bytes([9, 9, 9, 9, 0, 9]))
open(f"{s}/tmd/t3x2.tmd", "wb").write(t + struct.pack("<IIffff", 3, 2, 1.5, 0.5, 0.0, 0.0) + struct.pack("<6f", 1, 2, 3, 4, 5, 6))
PY
q convert "$T/h.npy" "$S/npy/h8_f32.npy" --f32
cp "$T/h.npy" "$S/npy/h8_f64.npy"
python3 - "$S/npy" <<'PY'
import struct, sys
d = sys.argv[1]
def npy(path, descr, shape, payload):
    h = "{'descr': '%s', 'fortran_order': False, 'shape': %s, }" % (descr, shape)
    h += " " * (63 - (10 + len(h)) % 64) + "\n"
    open(path, "wb").write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(h)) + h.encode() + payload)
npy(d + "/u8.npy", "|u1", "(3, 4)", bytes(range(12)))
npy(d + "/i4.npy", "<i4", "(2, 2)", struct.pack("<4i", 1, -2, 3, 4))
npy(d + "/points.npy", "<f8", "(2, 3)", struct.pack("<6d", 0, 0, 0, 1, 2, 3))
npy(d + "/big_endian.npy", ">f8", "(1, 2)", struct.pack(">2d", 1.5, 2.5))
PY
# A MountainsMap document (an OLE compound file) and a Mitutoyo workbook:
# written by their readers' own tests (which read them back on every run).
ASPERITY_WRITE_SEEDS=1 cargo test -q -p asperity-io --lib the_fuzz_seed_is >/dev/null
q convert "$T/h.npy" "$S/xyz/h8.xyz"
q subdiv --base cube --levels 1 -o "$T/c.ply"
q convert "$T/c.ply" "$S/ply/cube_binary.ply"
q convert "$T/c.ply" "$S/ply/cube_ascii.ply" --ascii
q convert "$T/c.ply" "$S/obj/cube.obj"
q convert "$T/c.ply" "$S/stl/cube.stl"
q convert "$S/xyz/h8.xyz" "$S/ply/points.ply"
q surface-ca builtin:cube --cells 200 --sites 3 -o "$T/v.ply"
cp "$T/v.ply" "$S/ply/colored.ply"
printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' > "$S/stl/ascii.stl"
printf 'v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n' > "$S/obj/quad_uv.obj"
printf '0,0\n1,0.5\n# comment\n2 1\n' > "$S/xy/curve.csv"
cp crates/subdiv/scenes/*.toml "$S/scene_toml/"
cp crates/ifs/presets/*.json "$S/ifs_json/"
q subdiv --base cube --levels 2 --detail rock --export-details "$S/detail_json/rock.json" -o "$T/r.ply"
printf '0.2 -1\n0.5 0\n0.2 1\n' > "$S/profile/vase.txt"
printf '0\n0.5\n1\n0.25\n0\n0\n1\n1\n' > "$S/alpha_map/cube.txt"
du -sh "$S"
