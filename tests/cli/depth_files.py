"""Depth images and masks for the tests, written without numpy or PIL (standard
library only): 16-bit and 8-bit grey PNGs, float32 .npy files, and a camera
above the table scene's target with its view and mask."""

import struct
import zlib


def png(width, height, values, bits=16):
    """A grey PNG of values (row-major) with 8 or 16 bits per pixel."""
    pack = ">%dH" % width if bits == 16 else "%dB" % width
    raw = b"".join(b"\0" + struct.pack(pack, *values[y * width:(y + 1) * width])
                   for y in range(height))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data)))
    return (b"\x89PNG\r\n\x1a\n"
            + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bits, 0, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def npy(width, height, values):
    """A NumPy .npy file of float32 values, height rows of width."""
    header = f"{{'descr': '<f4', 'fortran_order': False, 'shape': ({height}, {width}), }}"
    header = header.ljust(117) + "\n"  # the data starts at 128 bytes, as numpy writes it
    return (b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode()
            + struct.pack(f"<{len(values)}f", *values))


# A camera 1.2 m above the table scene's target, looking straight down: it
# sees the table top (z = 0) everywhere, the mug in the middle (masked).
WIDTH, HEIGHT = 32, 24
CAMERA = {"intrinsics": {"fx": 40, "fy": 40, "cx": 15.5, "cy": 11.5},
          "pose": {"position": [0.55, 0, 1.2], "orientation": [1, 0, 0, 0]}}
MUG = [1 if abs(u - 15.5) < 3 and abs(v - 11.5) < 3 else 0
       for v in range(HEIGHT) for u in range(WIDTH)]
