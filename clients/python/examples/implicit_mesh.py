"""POST /implicit/mesh: a unit sphere meshed at resolution 32: closed (every edge in two triangles), vertices on it."""
import math
from collections import Counter

from _common import check, client

r = client.implicit_mesh({"op": "sphere", "radius": 1}, [[-1.5, -1.5, -1.5], [1.5, 1.5, 1.5]], resolution=32,
                         output={"format": "json"})
mesh = r.json["mesh"]
off = max(abs(math.hypot(*p) - 1) for p in mesh["positions"])
edges = Counter(tuple(sorted((f[i], f[(i + 1) % len(f)]))) for f in mesh["faces"] for i in range(len(f)))
check(len(mesh["faces"]) > 500, f"{len(mesh['faces'])} triangles, grid {r.header('X-Grid')}")
check(off < 0.02, f"vertices on the sphere: max | |p| - 1 | = {off:.2e} (cell size 0.094)")
check(set(edges.values()) == {2}, "closed: every edge is shared by exactly two triangles")

try:
    import numpy
except ImportError:
    numpy = None
if numpy is not None:   # the same mesh as arrays: positions (N, 3) float64, faces (M, 3) int64
    positions, faces = r.mesh_arrays()
    radii = numpy.linalg.norm(positions, axis=1)
    check(faces.shape == (len(mesh["faces"]), 3) and abs(float(numpy.abs(radii - 1).max()) - off) < 1e-12,
          f"mesh_arrays: positions {positions.shape}, faces {faces.shape}")
else:
    print("skip mesh_arrays (numpy is not installed)")
