#!/usr/bin/env python3
"""Writes the binary files of the malformed STL, PLY, basis and Gmsh corpus (run from this
directory), and ../volume/two_tets_41_big_endian.msh, a valid big-endian MSH 4.1 file.

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

# MSH 4.1 binary: two tetrahedra on five nodes, one volume entity (tag 1, physical group 5).
MSH_NODES = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 1.0, 1.0)]
MSH_TETS = [(1, 2, 3, 4), (2, 3, 5, 4)]


def msh41(version=b"4.1 1 8", check=1, node_count=5, block_nodes=5, nodes=MSH_NODES,
          element_type=4, elements=MSH_TETS, end_nodes=b"$EndNodes", order="<"):
    """An MSH 4.1 binary file; the arguments break one thing at a time."""

    def sizes(*values):
        return struct.pack(f"{order}{len(values)}Q", *values)

    def ints(*values):
        return struct.pack(f"{order}{len(values)}i", *values)

    def reals(*values):
        return struct.pack(f"{order}{len(values)}d", *values)

    entities = sizes(0, 0, 0, 1) + ints(1) + reals(0, 0, 0, 1, 1, 1) + sizes(1) + ints(5) + sizes(0)
    node_data = (sizes(1, node_count, 1, node_count) + ints(3, 1, 0) + sizes(block_nodes)
                 + sizes(*range(1, len(nodes) + 1)) + reals(*(x for node in nodes for x in node)))
    element_data = (sizes(1, len(elements), 1, len(elements)) + ints(3, 1, element_type)
                    + sizes(len(elements))
                    + b"".join(sizes(tag, *corners) for tag, corners in enumerate(elements, 1)))
    return (b"$MeshFormat\n" + version + b"\n" + ints(check) + b"\n$EndMeshFormat\n$Entities\n"
            + entities + b"\n$EndEntities\n$Nodes\n" + node_data + b"\n" + end_nodes
            + b"\n$Elements\n" + element_data + b"\n$EndElements\n")


# In these files the $Nodes data starts at byte 175: header (32 bytes), block header (20), five
# tags (40), coordinates from byte 267 (24 per node). The $Elements data starts at byte 408:
# header (32), block header (20: element type at 448), elements from byte 460 (40 each).
valid = msh41()
assert valid.index(b"$Nodes\n") + 7 == 175 and valid.index(b"$Elements\n") + 10 == 408
# The same file big-endian: a valid mesh the reader must accept.
(HERE.parent / "volume" / "two_tets_41_big_endian.msh").write_bytes(msh41(order=">"))
# Cut 4 bytes into the last node's z (byte 267 + 4 * 24 + 16 = 379).
write("gmsh/msh41_truncated_binary.msh", valid[:383])
# The endianness check (byte 20) reads 2.
write("gmsh/msh41_endianness.msh", msh41(check=2))
# size_t of 4 bytes, which Gmsh writes on 32-bit systems.
write("gmsh/msh41_data_size_4.msh", msh41(version=b"4.1 1 4"))
# The header declares 4 nodes, the block 5 (its count at byte 175 + 32 + 12 = 219).
write("gmsh/msh41_binary_node_count.msh", msh41(node_count=4))
# The second tetrahedron's third node is tag 9 (byte 460 + 40 + 24 = 524).
write("gmsh/msh41_binary_undefined_node.msh", msh41(elements=[(1, 2, 3, 4), (2, 3, 9, 4)]))
# 2000000000 nodes declared (byte 183) in a file of 554 bytes.
write("gmsh/msh41_binary_hostile_count.msh", msh41(node_count=2_000_000_000))
# The fourth node's y is NaN (byte 267 + 3 * 24 + 8 = 347).
write("gmsh/msh41_binary_nan.msh",
      msh41(nodes=MSH_NODES[:3] + [(0.0, math.nan, 1.0)] + MSH_NODES[4:]))
# A block of ten-node tetrahedra (type at byte 448).
write("gmsh/msh41_binary_second_order.msh",
      msh41(element_type=11, elements=[(1, 2, 3, 4, 5, 1, 2, 3, 4, 5)]))
# "$EndNode" where "$EndNodes" belongs (byte 175 + 32 + 20 + 40 + 120 + 1 = 388).
write("gmsh/msh41_binary_missing_end.msh", msh41(end_nodes=b"$EndNode"))
