#!/usr/bin/env python3
"""Writes the mesh repair corpus: small files with the defects real exports have, one defect (or one reader quirk)
per file. tests/io/repair_corpus_test.cpp reads every file through the service's reader path, repairs it and checks
the counts listed in expected.json next to this script.

The outputs are committed; rerun this script (from any directory, Python 3, standard library only) after changing a
case, then update expected.json. Output is deterministic: the same bytes on every run.
"""
import base64
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, data):
    if isinstance(data, str):
        data = data.encode("ascii")
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def num(x):
    """Shortest text that reads back as the same double (integers without a fraction)."""
    return str(int(x)) if float(x).is_integer() else repr(float(x))


# ---- shapes: (positions, faces), faces 0-based and outward ------------------------------------------------------

# Unit cube [0,1]^3; its quads counter-clockwise seen from outside.
CUBE_POSITIONS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def triangulated(quads):
    return [t for (a, b, c, d) in quads for t in ((a, b, c), (a, c, d))]


CUBE_TRIANGLES = triangulated(CUBE_QUADS)  # 12


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def signed_volume(positions, faces):
    v = 0.0
    for f in faces:
        p0 = positions[f[0]]
        for j in range(1, len(f) - 1):
            p1, p2 = positions[f[j]], positions[f[j + 1]]
            v += sum(x * y for x, y in zip(p0, cross(p1, p2))) / 6.0
    return v


def outward(positions, faces):
    """The faces reversed when the closed surface they bound has a negative volume."""
    return faces if signed_volume(positions, faces) > 0 else [tuple(reversed(f)) for f in faces]


def moved(positions, offset):
    return [tuple(p + o for p, o in zip(q, offset)) for q in positions]


def subdivided_cube(size, n):
    """A cube of edge `size` with every side split into n x n squares, two triangles each: indexed, outward."""
    positions, index, faces = [], {}, []

    def vertex(p):
        if p not in index:
            index[p] = len(positions)
            positions.append(p)
        return index[p]

    step = size / n
    # each side: origin, u, v with u x v pointing outward
    sides = [((0, 0, 0), (0, 1, 0), (1, 0, 0)), ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
             ((0, 0, 0), (1, 0, 0), (0, 0, 1)), ((1, 0, 0), (0, 1, 0), (0, 0, 1)),
             ((0, 1, 0), (0, 0, 1), (1, 0, 0)), ((0, 0, 0), (0, 0, 1), (0, 1, 0))]
    for origin, u, v in sides:
        def at(i, j):
            return vertex(tuple(size * o + step * (i * a + j * b) for o, a, b in zip(origin, u, v)))
        for i in range(n):
            for j in range(n):
                a, b, c, d = at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)
                faces += [(a, b, c), (a, c, d)]
    assert signed_volume(positions, faces) > 0
    return positions, faces


def torus(major, minor, R, r):
    positions = []
    for i in range(major):
        u = 2 * math.pi * i / major
        for j in range(minor):
            v = 2 * math.pi * j / minor
            positions.append(((R + r * math.cos(v)) * math.cos(u), (R + r * math.cos(v)) * math.sin(u), r * math.sin(v)))
    faces = []
    for i in range(major):
        for j in range(minor):
            a = i * minor + j
            b = ((i + 1) % major) * minor + j
            c = ((i + 1) % major) * minor + (j + 1) % minor
            d = i * minor + (j + 1) % minor
            faces.append((a, b, c, d))
    return positions, outward(positions, faces)


def octahedron():
    positions = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    faces = []
    for x in (0, 1):
        for y in (2, 3):
            for z in (4, 5):
                faces.append((x, y, z))
    # orient each triangle outward: its normal points away from the origin
    oriented = []
    for f in faces:
        p = [positions[i] for i in f]
        n = cross(sub(p[1], p[0]), sub(p[2], p[0]))
        oriented.append(f if sum(a * b for a, b in zip(n, p[0])) > 0 else (f[0], f[2], f[1]))
    return positions, oriented


def square_pyramid(apex, base_z):
    """Apex and a square base of half-width 1 at height base_z: 5 vertices, 4 triangles and 1 quad, outward."""
    positions = [apex] + [(x, y, base_z) for x, y in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
    faces = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 1), (1, 4, 3, 2)]
    return positions, outward(positions, faces)


# ---- writers -----------------------------------------------------------------------------------------------------

def obj_text(header, positions, faces):
    lines = ["# " + line for line in header.splitlines()]
    lines += ["v " + " ".join(num(c) for c in p) for p in positions]
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    return "\n".join(lines) + "\n"


def off_text(header, positions, faces):
    lines = ["OFF"] + ["# " + line for line in header.splitlines()]
    lines.append(f"{len(positions)} {len(faces)} 0")
    lines += [" ".join(num(c) for c in p) for p in positions]
    lines += [" ".join([str(len(f))] + [str(i) for i in f]) for f in faces]
    return "\n".join(lines) + "\n"


def normal_of(tri):
    n = cross(sub(tri[1], tri[0]), sub(tri[2], tri[0]))
    length = math.sqrt(sum(c * c for c in n))
    return tuple(c / length for c in n)


def binary_stl(header, triangles):
    out = bytearray(header.encode("ascii").ljust(80, b" ")[:80])
    out += struct.pack("<I", len(triangles))
    for tri in triangles:
        out += struct.pack("<3f", *normal_of(tri))
        for p in tri:
            out += struct.pack("<3f", *p)
        out += struct.pack("<H", 0)
    return bytes(out)


def ascii_stl(name, triangles):
    lines = [f"solid {name}"]
    for tri in triangles:
        lines.append("  facet normal 0 0 0")  # many exporters write zero normals; readers must not rely on them
        lines.append("    outer loop")
        lines += ["      vertex " + " ".join(num(c) for c in p) for p in tri]
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append(f"endsolid {name}")
    return "\n".join(lines) + "\n"


def corners(positions, faces):
    return [tuple(positions[i] for i in f) for f in faces]


# ---- the cases ---------------------------------------------------------------------------------------------------

def soup_binary_stl():
    # A 20 mm cube, each side 2 x 2 squares: 48 triangles, every one with its own three corners (as STL stores them).
    positions, faces = subdivided_cube(20.0, 2)
    write("soup_binary.stl", binary_stl("binary STL: 20 mm cube, 2x2 squares per side, 48 triangles",
                                        corners(positions, faces)))


def soup_ascii_stl():
    # A triangular prism (6 corners, 8 triangles) whose exporter wrote two facets (4 and 6) wound backwards.
    positions = [(0, 0, 0), (4, 0, 0), (0, 3, 0), (0, 0, 5), (4, 0, 5), (0, 3, 5)]
    faces = outward(positions, [(0, 2, 1), (3, 4, 5), (0, 1, 4), (0, 4, 3), (1, 2, 5), (1, 5, 4), (2, 0, 3),
                                (2, 3, 5)])
    tris = corners(positions, faces)
    for k in (4, 6):
        tris[k] = tuple(reversed(tris[k]))
    write("soup_flipped_facets_ascii.stl", ascii_stl("prism", tris))


def soup_obj():
    # An octahedron as an OBJ triangle soup: every triangle its own three `v` lines (24), nothing shared by index.
    positions, faces = octahedron()
    soup_positions = [positions[i] for f in faces for i in f]
    soup_faces = [(3 * k, 3 * k + 1, 3 * k + 2) for k in range(len(faces))]
    write("soup_octahedron.obj", obj_text("octahedron, one vertex per triangle corner", soup_positions, soup_faces))


def back_to_back():
    # A double-sided 2 x 2 grid: every triangle also present with the opposite winding on the same vertices.
    positions = [(i, j, 0) for j in range(3) for i in range(3)]
    faces = []
    for j in range(2):
        for i in range(2):
            a, b, c, d = j * 3 + i, j * 3 + i + 1, (j + 1) * 3 + i + 1, (j + 1) * 3 + i
            faces += [(a, b, c), (a, c, d)]
    faces += [tuple(reversed(f)) for f in faces]
    write("back_to_back_faces.obj", obj_text("double-sided plane: 8 triangles, then each again reversed",
                                             positions, faces))


def fin():
    # A closed cube with a third triangle on its bottom-right edge (vertices 1-2), sticking out like a fin.
    positions = CUBE_POSITIONS + [(2, 0.5, -1)]
    faces = CUBE_TRIANGLES + [(1, 2, 8)]
    write("fin.obj", obj_text("unit cube plus a fin triangle on edge 2-3 (1-based)", positions, faces))


def bowtie():
    # Two open fans of three triangles in the plane z = 0 that meet only in their centre vertex.
    positions = [(0, 0, 0), (2, 0, 0), (2, 1, 0), (1, 2, 0), (0, 2, 0), (-2, 0, 0), (-2, -1, 0), (-1, -2, 0),
                 (0, -2, 0)]
    faces = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 5, 6), (0, 6, 7), (0, 7, 8)]
    write("bowtie.obj", obj_text("two fans meeting in one vertex", positions, faces))


def boxes_sharing_edge():
    # Two closed unit cubes along the diagonal sharing the edge x = y = 1: four faces around that edge, no T-junction.
    positions = list(CUBE_POSITIONS)
    index = {}
    for i, p in enumerate(moved(CUBE_POSITIONS, (1, 1, 0))):
        if p in positions:
            index[i] = positions.index(p)
        else:
            index[i] = len(positions)
            positions.append(p)
    faces = CUBE_TRIANGLES + [tuple(index[i] for i in f) for f in CUBE_TRIANGLES]
    write("boxes_sharing_edge.obj", obj_text("two cubes sharing one edge (x = y = 1)", positions, faces))


def flipped_components():
    # Two closed cubes: the first with three triangles wound backwards, the second entirely inside out.
    positions = CUBE_POSITIONS + moved(CUBE_POSITIONS, (3, 0, 0))
    first = [tuple(reversed(f)) if k in (1, 5, 8) else f for k, f in enumerate(CUBE_TRIANGLES)]
    second = [tuple(8 + i for i in reversed(f)) for f in CUBE_TRIANGLES]
    write("flipped_components.obj", obj_text("cube with triangles 2, 6, 9 reversed; a second cube inside out",
                                             positions, first + second))


def pinched_pyramids():
    # Two square pyramids tip to tip, the apex one shared vertex: a pinched (non-manifold) vertex. Bases are quads.
    up_positions, up_faces = square_pyramid((0, 0, 0), 1)
    down_positions, down_faces = square_pyramid((0, 0, 0), -1)
    positions = up_positions + down_positions[1:]
    shift = {0: 0, 1: 5, 2: 6, 3: 7, 4: 8}
    faces = up_faces + [tuple(shift[i] for i in f) for f in down_faces]
    write("pinched_pyramids.off", off_text("two square pyramids touching at their apex (vertex 0)", positions, faces))


def degenerate_faces():
    # A closed cube plus zero-area faces: a repeated index, three collinear points, a corner that welds onto another.
    positions = CUBE_POSITIONS + [(3, 0, 0), (4, 1, 1), (6, 3, 3), (1, 0, 0)]
    faces = CUBE_TRIANGLES + [(0, 1, 1), (8, 9, 10), (1, 11, 5)]
    write("degenerate_faces.obj",
          obj_text("unit cube; f 1 2 2 repeats a vertex, 9-10-11 are collinear, 12 sits on 2", positions, faces))


def clean_torus():
    # A closed, consistently oriented torus of 8 x 6 quads: nothing to repair, must come back unchanged.
    positions, faces = torus(8, 6, 2.0, 0.5)
    write("clean_torus.obj", obj_text("closed torus, 8 x 6 quads: needs no repair", positions, faces))


def blender_ply():
    # A flat-shaded cube as old Blender exports wrote it: four vertices per quad (normals differ per face), and a
    # "Created by ..." line in the header that is not a PLY keyword.
    lines = ["ply", "format ascii 1.0", "Created by Blender 2.49 - www.blender.org, source file: 'cube.blend'",
             "element vertex 24", "property float x", "property float y", "property float z",
             "property float nx", "property float ny", "property float nz",
             "element face 6", "property list uchar uint vertex_indices", "end_header"]
    faces = []
    for quad in CUBE_QUADS:
        p = [CUBE_POSITIONS[i] for i in quad]
        n = normal_of(p[:3])
        base = len(faces) * 4
        for q in p:
            lines.append(" ".join(num(c) for c in q + n))
        faces.append((base, base + 1, base + 2, base + 3))
    lines += ["4 " + " ".join(str(i) for i in f) for f in faces]
    write("blender249_flat_cube.ply", "\n".join(lines) + "\n")


def gltf_nested():
    # One mesh, a unit cube, as two TRIANGLES primitives (6 triangles each, each with its own 8 vertices in a
    # different order) and one POINTS primitive (3 points off the cube). It is instanced by node 1, a child of node 0:
    #   node 0: translation (10, 0, 0), rotation 90 degrees about +z, scale 2
    #   node 1: translation (0, 0, 1), scale (1, 1, 3), mesh 0
    # World position of a local (x, y, z): node 1 gives (x, y, 3z + 1); node 0 scales by 2, turns (x, y) into
    # (-y, x) and adds (10, 0, 0): (10 - 2y, 2x, 6z + 2).
    first_order = list(range(8))
    second_order = [6, 2, 7, 3, 5, 1, 4, 0]
    prims = []
    buffer = bytearray()
    views, accessors = [], []

    def add_view(data, target):
        while len(buffer) % 4:
            buffer.append(0)
        views.append({"buffer": 0, "byteOffset": len(buffer), "byteLength": len(data), "target": target})
        buffer.extend(data)
        return len(views) - 1

    def add_positions(points):
        view = add_view(b"".join(struct.pack("<3f", *p) for p in points), 34962)
        accessors.append({"bufferView": view, "componentType": 5126, "count": len(points), "type": "VEC3",
                          "min": [min(p[k] for p in points) for k in range(3)],
                          "max": [max(p[k] for p in points) for k in range(3)]})
        return len(accessors) - 1

    def add_indices(indices):
        view = add_view(b"".join(struct.pack("<H", i) for i in indices), 34963)
        accessors.append({"bufferView": view, "componentType": 5123, "count": len(indices), "type": "SCALAR"})
        return len(accessors) - 1

    for order, triangles in ((first_order, CUBE_TRIANGLES[:6]), (second_order, CUBE_TRIANGLES[6:])):
        where = {v: k for k, v in enumerate(order)}
        position = add_positions([CUBE_POSITIONS[v] for v in order])
        indices = add_indices([where[v] for t in triangles for v in t])
        prims.append({"attributes": {"POSITION": position}, "indices": indices, "mode": 4})
    prims.append({"attributes": {"POSITION": add_positions([(5, 5, 5), (6, 5, 5), (5, 6, 5)])}, "mode": 0})
    document = {
        "asset": {"version": "2.0", "generator": "surfaced tests/data/repair-corpus/generate.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"name": "parent", "translation": [10, 0, 0], "rotation": [0, 0, math.sqrt(0.5), math.sqrt(0.5)],
             "scale": [2, 2, 2], "children": [1]},
            {"name": "child", "translation": [0, 0, 1], "scale": [1, 1, 3], "mesh": 0},
        ],
        "meshes": [{"name": "cube in two parts, and three points", "primitives": prims}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(buffer),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buffer)).decode()}],
    }
    write("nested_transforms.gltf", json.dumps(document, indent=1) + "\n")


# ---- not meshes: the service must refuse them (4xx), not crash ------------------------------------------------

def point_cloud_ply():
    # A scan as a PLY point cloud: vertices only, no face element.
    points = [(math.cos(k * 0.7) * (1 + 0.01 * k), math.sin(k * 0.7) * (1 + 0.01 * k), 0.05 * k) for k in range(20)]
    lines = ["ply", "format ascii 1.0", "comment a point cloud: no faces", "element vertex 20", "property float x",
             "property float y", "property float z", "end_header"]
    lines += [" ".join(repr(round(c, 6)) for c in p) for p in points]
    write("not_a_mesh_point_cloud.ply", "\n".join(lines) + "\n")


def only_degenerate():
    # Faces, but none with an area: collinear corners and repeated indices.
    positions = [(0, 0, 0), (1, 1, 1), (2, 2, 2), (3, 3, 3)]
    faces = [(0, 1, 2), (1, 2, 3), (0, 0, 3)]
    write("not_a_mesh_only_degenerate.obj", obj_text("every face has zero area", positions, faces))


if __name__ == "__main__":
    soup_binary_stl()
    soup_ascii_stl()
    soup_obj()
    back_to_back()
    fin()
    bowtie()
    boxes_sharing_edge()
    flipped_components()
    pinched_pyramids()
    degenerate_faces()
    clean_torus()
    blender_ply()
    gltf_nested()
    point_cloud_ply()
    only_degenerate()
