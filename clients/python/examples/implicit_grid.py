"""POST /implicit/grid: a tetrahedron as a narrow-band signed distance grid, sent back as a scene and queried."""
from _common import check, client

tet = {"positions": [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]],
       "faces": [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]}
grid = client.implicit_grid(mesh=tet, voxel_size=0.25, band=2).json
check(grid["op"] == "level_set" and len(grid["values"]) == grid["dims"][0] * grid["dims"][1] * grid["dims"][2],
      f"a level_set node of {grid['dims']} nodes")
check(max(abs(v) for v in grid["values"]) <= 0.5 + 1e-12, "values clamped to the band, 2 * 0.25")
r = client.implicit_query(grid, points=[[0, 0, 0], [3, 0, 0]]).json
classes = [p["class"] for p in r["points"]]
check(classes == ["inside", "outside"], f"classes {classes}")
