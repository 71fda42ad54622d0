#!/usr/bin/env python3
"""Writes the binary files of the malformed STL, PLY and basis corpus (run from this directory).

The text cases are committed as they are; these are generated because they are easier to
read as code than as hex dumps. Byte offsets the tests expect are noted next to each case.
"""

import math
import struct
from pathlib import Path

HERE = Path(__file__).resolve().parent

TRIANGLE = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]


def stl(count, triangles, header=b"binary STL test case"):
    body = b"".join(
        struct.pack("<3f", 0.0, 0.0, 1.0)
        + b"".join(struct.pack("<3f", *corner) for corner in triangle)
        + b"\0\0"
        for triangle in triangles
    )
    return header.ljust(80, b" ") + struct.pack("<I", count) + body


def ply_header(encoding, vertices, faces, count_type="uchar"):
    return (
        f"ply\nformat {encoding} 1.0\n"
        f"element vertex {vertices}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {faces}\nproperty list {count_type} int vertex_indices\nend_header\n"
    ).encode()


def write(name, data):
    (HERE / name).write_bytes(data)


# Declares 3 triangles but holds 2: 184 bytes instead of 234.
write("stl/binary_size_mismatch.stl", stl(3, [TRIANGLE, TRIANGLE]))
# Declares 2000000000 triangles in a 134-byte file.
write("stl/hostile_count.stl", stl(2_000_000_000, [TRIANGLE]))
# Second corner's y is NaN: byte 84 + 12 (normal) + 12 (first corner) + 4 (x) = 112.
write("stl/nan_coordinate_binary.stl",
      stl(1, [[(0.0, 0.0, 0.0), (1.0, math.nan, 0.0), (0.0, 1.0, 0.0)]]))

vertices_le = b"".join(struct.pack("<3f", *corner) for corner in TRIANGLE)
# 2147483647 vertices of 12 bytes each declared in a file of about 200 bytes.
write("ply/hostile_count_binary.ply",
      ply_header("binary_little_endian", 2**31 - 1, 1) + vertices_le + b"\x03" + struct.pack("<3i", 0, 1, 2))
# The face's list claims 200 indices (800 bytes); 12 bytes follow the count.
write("ply/binary_list_too_long.ply",
      ply_header("binary_little_endian", 3, 1) + vertices_le + b"\xc8" + struct.pack("<3i", 0, 1, 2))
# A signed list count of -1.
write("ply/negative_list_length.ply",
      ply_header("binary_little_endian", 3, 1, count_type="char") + vertices_le + b"\xff"
      + struct.pack("<3i", 0, 1, 2))
# Two faces declared, one present: the second face's count byte is missing.
write("ply/truncated_binary.ply",
      ply_header("binary_little_endian", 3, 2) + vertices_le + b"\x03" + struct.pack("<3i", 0, 1, 2))
# Big-endian file whose second vertex has x = +inf.
write("ply/inf_coordinate_binary.ply",
      ply_header("binary_big_endian", 3, 1)
      + struct.pack(">9f", 0, 0, 0, math.inf, 0, 0, 0, 1, 0) + b"\x03" + struct.pack(">3i", 0, 1, 2))

# Basis files: damaged copies of the committed version-1 file (315 bytes). Each damage is one
# the container must report before it looks at the payload, so no checksum is recomputed here.
basis = (HERE.parent / "basis" / "tet_v1.khzbasis").read_bytes()
assert len(basis) == 315 and basis[:8] == b"KHZBASIS"
write("basis/empty.khzbasis", b"")
# Another format's bytes: rejected by the magic at byte 0.
write("basis/not_basis.khzbasis", ply_header("binary_little_endian", 3, 1) + vertices_le)
# Format version 2 at byte 8: checked before the checksum, which a newer format may change.
write("basis/future_version.khzbasis", basis[:8] + struct.pack("<I", 2) + basis[12:])
# Cut inside the 8-byte file length at byte 12.
write("basis/truncated_header.khzbasis", basis[:16])
# Cut inside U: the header declares 315 bytes.
write("basis/truncated.khzbasis", basis[:200])
# One bit of U flipped: only the checksum (at byte 307) can tell.
write("basis/flipped_byte.khzbasis", basis[:250] + bytes([basis[250] ^ 0x01]) + basis[251:])
# Four bytes after the checksum.
write("basis/trailing_bytes.khzbasis", basis + b"junk")
