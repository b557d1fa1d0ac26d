#!/usr/bin/env python3
"""Writes the binary cases of the malformed-file corpus (tests/io/malformed_test.cpp lists what each must give).

The outputs are committed next to this script; rerun it (from any directory) after changing a case. The text
cases in this directory are written by hand. Offsets named in the test table follow from the layouts below.
"""
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


TRIANGLE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"

# ---- encodings and garbage, one per text format
for ext in ("obj", "off", "ply", "stl"):
    text = {"obj": TRIANGLE_OBJ,
            "off": "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
            "ply": "ply\nformat ascii 1.0\nend_header\n",
            "stl": "solid t\nendsolid t\n"}[ext]
    write(f"{ext}_utf16le_bom.{ext}", b"\xff\xfe" + text.encode("utf-16-le"))
write("obj_utf16be_bom.obj", b"\xfe\xff" + TRIANGLE_OBJ.encode("utf-16-be"))
write("obj_utf16le_nobom.obj", TRIANGLE_OBJ.encode("utf-16-le"))
write("obj_utf16le_odd.obj", (b"\xff\xfe" + TRIANGLE_OBJ.encode("utf-16-le"))[:-1])

rng = random.Random(1234)  # fixed seed: the files must not change between runs
garbage = bytes(rng.randrange(256) for _ in range(300))
assert b"\0" in garbage
write("obj_binary_garbage.obj", garbage)
write("off_garbage.off", garbage)
write("ply_garbage.ply", garbage)
# High bytes and control characters but no NUL: must still be a clean ParseError, not "no faces".
write("obj_high_bytes.obj", bytes([0x8f, 0xe3, 0x01, 0x7f, 0x20, 0xc0, 0x0a]) * 20)
write("stl_short_garbage.stl", garbage[:30])

# ---- binary PLY
PLY_HEAD = ("ply\nformat binary_{endian}_endian 1.0\nelement vertex {nv}\nproperty {ct} x\nproperty {ct} y\n"
            "property {ct} z\nelement face {nf}\nproperty list {lt} uint vertex_indices\nend_header\n")


def ply(nv=3, nf=1, ct="float", lt="uchar", endian="little"):
    return PLY_HEAD.format(nv=nv, nf=nf, ct=ct, lt=lt, endian=endian).encode()


TRI_VERTS = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]


def verts(fmt="<3f", vs=TRI_VERTS):
    return b"".join(struct.pack(fmt, *v) for v in vs)


# truncated inside face 0: the count byte is there, then 4 of the 12 index bytes
head = ply()
data = head + verts() + struct.pack("<B", 3) + struct.pack("<I", 0)
write("ply_binary_truncated.ply", data)
print("ply_binary_truncated: truncated at", len(head) + 36 + 1)

# a UTF-16 header on a binary body (padded to whole UTF-16 units so that only the binary format is refused)
data = b"\xff\xfe" + ply().decode().encode("utf-16-le") + verts() + struct.pack("<BIII", 3, 0, 1, 2)
write("ply_utf16le_binary.ply", data + b"\0" * (len(data) % 2))

# 4e9 faces in a ~200 byte file
data = ply(nf=4000000000) + verts() + struct.pack("<BIII", 3, 0, 1, 2)
write("ply_binary_absurd_faces.ply", data)

# NaN in vertex 1
head = ply()
write("ply_binary_nan.ply", head + verts(vs=[(0, 0, 0), (1, float("nan"), 0), (0, 1, 0)]) + struct.pack("<BIII", 3, 0, 1, 2))
print("ply_binary_nan: vertex 1 at", len(head) + 12)

# face index 7 of 3 vertices: index k of face 0 sits at body + 36 + 1 + 4k
head = ply()
write("ply_binary_index_out_of_range.ply", head + verts() + struct.pack("<BIII", 3, 0, 7, 2))
print("ply_binary_index_out_of_range: index at", len(head) + 36 + 1 + 4)

# negative list length with a signed count type
head = ply(lt="int")
write("ply_binary_negative_count.ply", head + verts() + struct.pack("<iIII", -1, 0, 1, 2))
print("ply_binary_negative_count: count at", len(head) + 36)

# a face of 1,000,000 vertices (over the default max_face_size) in a small file
head = ply(lt="uint")
write("ply_binary_huge_list.ply", head + verts() + struct.pack("<IIII", 1000000, 0, 1, 2))
print("ply_binary_huge_list: count at", len(head) + 36)

# a face of 60,000 vertices (within the limit) whose indices are not there
head = ply(lt="ushort")
write("ply_binary_list_past_end.ply", head + verts() + struct.pack("<HIII", 60000, 0, 1, 2))
print("ply_binary_list_past_end: indices at", len(head) + 36 + 2)

# big endian doubles with an infinity in vertex 2
head = ply(ct="double", endian="big")
write("ply_be_inf.ply", head + verts(">3d", [(0, 0, 0), (1, 0, 0), (0, float("inf"), 0)]) + struct.pack(">BIII", 3, 0, 1, 2))
print("ply_be_inf: vertex 2 at", len(head) + 48)

# a repeated vertex in a binary face
head = ply()
write("ply_binary_repeated.ply", head + verts() + struct.pack("<BIII", 3, 0, 1, 0))
print("ply_binary_repeated: face 0 at", len(head) + 36)

# ---- binary STL
def stl(triangles, count=None, header=b"binary"):
    out = header.ljust(80, b" ") + struct.pack("<I", len(triangles) if count is None else count)
    for t in triangles:
        out += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *p) for p in t) + b"\0\0"
    return out


T0 = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
T1 = [(1, 0, 0), (1, 1, 0), (0, 1, 0)]
write("stl_binary_truncated.stl", stl([T0] * 5, count=12))
write("stl_binary_absurd_count.stl", stl([T0, T1], count=4000000000) + b"\0" * 16)
write("stl_binary_nan.stl", stl([T0, [(1, 0, 0), (1, 1, 0), (float("nan"), 1, 0)]]))  # offset 84 + 50 + 12 + 24
write("stl_binary_inf.stl", stl([[(float("-inf"), 0, 0), (1, 0, 0), (0, 1, 0)]]))  # offset 84 + 12
write("stl_binary_all_degenerate.stl", stl([[(0, 0, 0), (0, 0, 0), (1, 1, 1)], [(2, 2, 2)] * 3]))
write("stl_binary_zero_triangles.stl", stl([]))
# "solid" header, NUL bytes, wrong size: a truncated binary file, not ascii
write("stl_binary_solid_truncated.stl", stl([T0, T1], count=3, header=b"solid exported"))
