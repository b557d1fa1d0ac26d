"""POST /pointcloud: 200 points sampled on a unit sphere (an implicit scene) with estimated normals: the points lie on
the sphere and each normal is radial (up to orientation); then an XYZ text upload."""
import math

from _common import check, client

r = client.pointcloud(sample={"scene": {"op": "sphere", "radius": 1}, "bounds": [[-1.5] * 3, [1.5] * 3],
                              "count": 200, "seed": 3},
                      estimate_normals={"k": 12}, output={"format": "json"})
doc = r.json
points, normals = doc["points"], doc["normals"]
off = max(abs(math.hypot(*p) - 1) for p in points)
radial = min(abs(sum(n[i] * p[i] for i in range(3))) / (math.hypot(*n) * math.hypot(*p)) for p, n in zip(points, normals))
check(len(points) == 200 and len(normals) == 200, f"{len(points)} points with normals")
check(off < 1e-3, f"on the sphere: max | |p| - 1 | = {off:.2e}")
check(radial > 0.9, f"estimated normals radial: min |cos| = {radial:.4f}")

xyz = client.pointcloud(data=b"0 0 0\n1 0 0\n0 1 0\n1 1 0.1\n", content_type="text/x-xyz", format="ply")
check(xyz.header("X-Output-Points") == "4" and xyz.body.startswith(b"ply"), "XYZ upload -> PLY with 4 points")

try:
    import numpy
except ImportError:
    numpy = None
if numpy is not None:   # as arrays: points (N, 3), normals (N, 3), colors None
    arrays = r.point_arrays()
    cosines = numpy.abs(numpy.einsum("ij,ij->i", arrays.points, arrays.normals))
    check(arrays.points.shape == (200, 3) and arrays.colors is None and cosines.min() > 0.9,
          f"point_arrays: points {arrays.points.shape}, normals {arrays.normals.shape}")
else:
    print("skip point_arrays (numpy is not installed)")
