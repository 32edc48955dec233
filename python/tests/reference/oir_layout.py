"""Olympus .oir and .poir files built to the layout SurfaceTopography's OIR.py
reads (after Gwyddion's oirfile.c); no OIR file is public in a repository
asperity can reach. Little-endian: the 96-byte header, then chunks (i32 size,
i32 type): a metadata list (version, properties XML, topography prefix,
dataset names, topography UUIDs), a BMP preview, one per-frame metadata
block, a data block per channel, and the end marker (size -1).

`python oir_layout.py OUT.oir` writes the small file of asperity-io's unit
tests (crates/io/tests/data/small.oir).
"""
import struct
import sys
import zipfile

import numpy as np

NS = ('xmlns:lsmimage="http://www.olympus.co.jp/hpf/model/lsmimage" '
      'xmlns:commonimage="http://www.olympus.co.jp/hpf/model/commonimage" '
      'xmlns:commonphase="http://www.olympus.co.jp/hpf/model/commonphase" '
      'xmlns:commonparam="http://www.olympus.co.jp/hpf/model/commonparam" '
      'xmlns:base="http://www.olympus.co.jp/hpf/model/base"')


def text(s):
    b = s.encode("ascii")
    return struct.pack("<I", len(b)) + b


def block(kind, content):
    return struct.pack("<I", kind) + struct.pack("<8I", 1, 1, 0, 0, 1, 1, 1, 1) + content


def chunk(kind, payload):
    return struct.pack("<ii", len(payload), kind) + payload


def properties(nx, ny, channels, calibration, microscope, date):
    """channels: (id, image type, depth, lengths (x, y, z), units (x, y, z))."""
    def axes(tag, ns, values):
        return f"<{tag}>" + "".join(f"<{ns}:{a}>{v}</{ns}:{a}>" for a, v in zip("xyz", values)) + f"</{tag}>"
    chans = "".join(
        f'<commonphase:channel id="{cid}" order="{k + 1}">'
        f"<commonphase:imageDefinition><commonphase:imageType>{kind}</commonphase:imageType>"
        f"<commonphase:depth>{depth}</commonphase:depth><commonphase:bitCounts>{8 * depth}</commonphase:bitCounts>"
        f"</commonphase:imageDefinition>"
        + axes("commonphase:length", "commonparam", lengths) + axes("commonphase:pixelUnit", "commonphase", units)
        + "</commonphase:channel>"
        for k, (cid, kind, depth, lengths, units) in enumerate(channels))
    calib = "".join(f"<commonparam:{a}>{v}</commonparam:{a}>" for a, v in calibration.items())
    return (f"<?xml version=\"1.0\" encoding=\"ASCII\"?><lsmimage:imageProperties {NS}>"
            f"<commonimage:general><base:creationDateTime>{date}</base:creationDateTime></commonimage:general>"
            f"<commonimage:microscope><base:name>{microscope}</base:name></commonimage:microscope>"
            f"<commonimage:imageInfo><commonimage:width>{nx}</commonimage:width>"
            f"<commonimage:height>{ny}</commonimage:height>"
            f"<commonimage:phase><commonphase:group>{chans}</commonphase:group></commonimage:phase>"
            f"</commonimage:imageInfo>"
            f"<commonimage:acquisition><commonimage:microscopeConfiguration>"
            f"<commonimage:pixelCalibration>{calib}</commonimage:pixelCalibration>"
            f"</commonimage:microscopeConfiguration></commonimage:acquisition>"
            f"</lsmimage:imageProperties>")


def oir_bytes(channels, calibration, microscope="OLS5000", date="2026-11-28T09:30:00.000+01:00",
              prefix="t001_0_1", lsm=True):
    """channels: (id, image type, counts (ny, nx) u1 or <u2, lengths, units)."""
    ny, nx = channels[0][2].shape
    desc = [(cid, kind, counts.dtype.itemsize, lengths, units) for cid, kind, counts, lengths, units in channels]
    props = properties(nx, ny, desc, calibration, microscope, date)
    if not lsm:
        props = props.replace("lsmimage:imageProperties", "cameraimage:imageProperties").replace(
            "xmlns:lsmimage", "xmlns:cameraimage")
    version = f"<?xml version=\"1.0\"?><fileinfo {NS}><version>1.2.0</version></fileinfo>"
    heights = [cid for cid, kind, *_ in channels if kind == "HEIGHT"]
    metadata = b"".join([
        block(1, text(version)),
        block(2, text(props)),
        block(3, text(f"<annotations {NS}/>")),
        block(6, struct.pack("<I", 1) + text(prefix) + struct.pack("<I", 0)),
        block(7, struct.pack("<I", len(channels))
              + b"".join(text(f"{prefix}_{cid}") + struct.pack("<I", 0) for cid, *_ in channels)),
        block(8, struct.pack("<I", len(heights)) + b"".join(text(h) + struct.pack("<I", 0) for h in heights)),
        block(9, struct.pack("<I", 1) + struct.pack("<I", 0) + text(prefix) + text(prefix)),
        block(14, text(f"<events {NS}/>")),
    ])
    body = chunk(0, metadata)
    bmp_pixels = b"\x10" * 24
    body += chunk(2, b"BMP\x00BM" + struct.pack("<I", len(bmp_pixels) + 6) + bmp_pixels)
    body += chunk(1, block(1, text(version)))
    for cid, kind, counts, *_ in channels:
        name = f"{prefix}_{cid}_0"
        data = np.ascontiguousarray(counts).tobytes()
        header = struct.pack("<II", 0, len(data)) + text(name)
        body += struct.pack("<ii", len(header), 3) + header + struct.pack("<II", len(data), 4) + data
    body += struct.pack("<ii", 0, 5)  # a spacer
    body += struct.pack("<i", -1)
    size = 96 + len(body)
    header = (b"OLYMPUSRAWFORMAT" + struct.pack("<14I", 12, 0, 1, 2, size, 0, 96, 0, 17, 0, 1, 0, 0, 0)
              + b"UNKNOWN\x00" + struct.pack("<4I", 1, 1, 0xFFFFFFFF, 0xFFFFFFFF))
    assert len(header) == 96
    return header + body


def poir_bytes(path, members):
    """A packed OIR: `members` (name, bytes) in a zip, with a non-OIR member."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("manifest.xml", "<manifest/>")
        for name, data in members:
            z.writestr(name, data)


if __name__ == "__main__":
    h1 = np.arange(15, dtype="<u2").reshape(3, 5)
    h2 = np.arange(15, dtype="u1").reshape(3, 5)
    data = oir_bytes([("h1", "HEIGHT", h1, (0.1, 0.1, 0.25), ("MICRO_METER", "MICRO_METER", "MICRO_METER")),
                      ("i1", "INTENSITY", h1, (0.1, 0.1, 1.0), ("MICRO_METER", "MICRO_METER", "MICRO_METER")),
                      ("h2", "HEIGHT", h2, (0.1, 0.1, 0.5), ("MICRO_METER", "MICRO_METER", "MICRO_METER"))],
                     {"x": 1.1, "z": 2.0})
    open(sys.argv[1], "wb").write(data)
