"""POST /surfaces: the closest point on a NURBS cylinder is the radial projection; elevating its degree keeps it."""
import math

from _common import check, client

h = math.sqrt(0.5)
# the 9-point rational quadratic circle of radius 1 (u), swept linearly from z = 0 to z = 2 (v)
circle = [(1, 0, 1), (1, 1, h), (0, 1, 1), (-1, 1, h), (-1, 0, 1), (-1, -1, h), (0, -1, 1), (1, -1, h), (1, 0, 1)]
cylinder = {"degree": [2, 1], "knots_u": [0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1],
            "knots_v": [0, 0, 1, 1], "points": [[x, y, z] for z in (0, 2) for x, y, _ in circle],
            "weights": [w for _ in (0, 2) for *_, w in circle]}
r = client.surfaces(cylinder, closest=[[3, 4, 1]], elevate={"direction": "v", "times": 2}, evaluate=[[0.1, 0.5]]).json
c = r["closest"][0]
check(abs(c["distance"] - 4) < 1e-9, f"distance {c['distance']}")  # |(3, 4)| - 1
check(all(abs(a - b) < 1e-6 for a, b in zip(c["point"], [0.6, 0.8, 1])), f"closest point {c['point']}")
again = client.surfaces(r["elevate"], evaluate=[[0.1, 0.5]]).json
check(r["elevate"]["degree"] == [2, 3], f"elevated degree {r['elevate']['degree']}")
check(max(abs(a - b) for a, b in zip(again["evaluate"][0]["position"], r["evaluate"][0]["position"])) < 1e-12,
      "the elevated surface is the same surface")
