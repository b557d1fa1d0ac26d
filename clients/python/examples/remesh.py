"""POST /remesh: an octahedron remeshed to edge length 0.25; the new vertices stay on its surface (|x|+|y|+|z| = 1)."""
from _common import check, client

octahedron = {
    "positions": [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]],
    "faces": [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]],
}
r = client.remesh(octahedron, edge_length=0.25, iterations=5, format="json")
mesh = r.json["mesh"]
off_surface = max(abs(abs(x) + abs(y) + abs(z) - 1) for x, y, z in mesh["positions"])
check(len(mesh["faces"]) > 8 * 10, f"8 -> {len(mesh['faces'])} triangles (min angle {r.header('X-Min-Angle-After')})")
check(off_surface < 1e-6, f"every vertex on the octahedron: max | |x|+|y|+|z| - 1 | = {off_surface:.2e}")
