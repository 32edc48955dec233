"""TIFF files built by hand to the layouts SurfaceTopography's readers expect
(no public instrument file of these kinds): shared by the instrument check
(check_instruments.py) and the JPK fuzz seeds (fuzz/jpk_seed.py)."""
import struct

import numpy as np


def tiff_bytes(pages):
    """A little-endian TIFF; each page a list of (tag, type, payload bytes,
    count); the payloads are placed after all directories."""
    type_size = {1: 1, 2: 1, 3: 2, 4: 4, 7: 1}
    out, blobs, fixups = bytearray(b"II*\0" + struct.pack("<I", 8)), bytearray(), []
    heads = []
    at = 8
    for page in pages:
        heads.append(at)
        at += 2 + 12 * len(page) + 4
    blob_base = at
    for k, page in enumerate(pages):
        out += struct.pack("<H", len(page))
        for tag, kind, payload, count in sorted(page, key=lambda e: e[0]):
            if callable(payload):  # an offset to a directory, known now
                payload = struct.pack("<I", payload(heads))
            if len(payload) <= 4:
                out += struct.pack("<HHI", tag, kind, count) + payload.ljust(4, b"\0")
            else:
                out += struct.pack("<HHII", tag, kind, count, blob_base + len(blobs))
                blobs += payload + b"\0" * (len(payload) % 2)
        # Pages chain to the next; the last directory (the LEXT EXIF one, or an
        # empty sentinel) is reached only through its pointer.
        out += struct.pack("<I", heads[k + 1] if k + 1 < len(pages) - 1 else 0)
    return bytes(out + blobs)


def jpk_bytes(counts, reflect):
    ny, nx = counts.shape
    asc = lambda t: (t.encode() + b"\0")  # noqa: E731
    image = lambda data, bits, fmt: [  # noqa: E731
        (256, 4, struct.pack("<I", nx), 1), (257, 4, struct.pack("<I", ny), 1), (258, 3, struct.pack("<H", bits), 1),
        (259, 3, struct.pack("<H", 1), 1), (262, 3, struct.pack("<H", 1), 1), (273, 4, data, 1),
        (277, 3, struct.pack("<H", 1), 1), (278, 4, struct.pack("<I", ny), 1),
        (279, 4, struct.pack("<I", len(data)), 1), (339, 3, struct.pack("<H", fmt), 1)]
    first = image(np.zeros((ny, nx), "u1").tobytes(), 8, 1) + [
        (0x8003, 2, asc("2026-11-28T20:10:00.000+00:00"), 30), (0x8042, 12, struct.pack("<d", 2e-6), 1),
        (0x8043, 12, struct.pack("<d", 1.5e-6), 1), (0x8045, 4, struct.pack("<I", reflect), 1)]

    def channel(fancy, retrace, unit, data):
        tags = [(0x8050, 2, asc(fancy.lower()), len(fancy) + 1), (0x8051, 4, struct.pack("<I", retrace), 1),
                (0x8052, 2, asc(fancy), len(fancy) + 1), (0x8080, 4, struct.pack("<I", 2), 1),
                (0x8081, 2, asc("nominal"), 8)]
        for k, (name, u, mult, off) in enumerate([("raw", "V", 1.0, 0.0), ("nominal", unit, 2.5e-10, 1e-7)]):
            base = 0x8090 + 0x30 * k
            tags += [(base, 2, asc(name), len(name) + 1), (base + 0x12, 2, asc(u), len(u) + 1),
                     (base + 0x13, 2, asc("LinearScaling"), 14), (base + 0x14, 12, struct.pack("<d", mult), 1),
                     (base + 0x15, 12, struct.pack("<d", off), 1)]
        return image(data.astype("<i4").tobytes(), 32, 2) + tags
    return tiff_bytes([first, channel("Height (measured)", 0, "m", counts), channel("Height (measured)", 1, "m", -counts),
                       channel("Vertical Deflection", 0, "V", counts)] + [[]])
