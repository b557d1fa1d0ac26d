"""POST /limit/evaluate: the limit surface of a flat 2 x 2 grid with sharp corners is its own plane."""
from _common import check, client

grid = {"positions": [[x / 2, y / 2, 0] for y in range(3) for x in range(3)],
        "faces": [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]],
        "uvs": [[x / 2, y / 2] for y in range(3) for x in range(3)],
        "uv_faces": [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]]}
r = client.limit_evaluate(grid, [{"face": 0, "uv": [0.5, 0.5]}, {"face": 3, "uv": [1, 1]}],
                          boundary="edge-and-corner", uv_interpolation="all", derivatives=2).json
p = r["points"]
check(all(abs(a - b) < 1e-12 for a, b in zip(p[0]["position"], [0.25, 0.25, 0])), f"position {p[0]['position']}")
check(all(abs(a - b) < 1e-12 for a, b in zip(p[1]["position"], [1, 1, 0])), "the sharp corner is interpolated")
check(all(abs(a - b) < 1e-12 for a, b in zip(p[0]["normal"], [0, 0, 1])), f"normal {p[0]['normal']}")
check(all(abs(a - b) < 1e-12 for a, b in zip(p[0]["uv"], [0.25, 0.25])), f"uv {p[0]['uv']}")
check(all(abs(c) < 1e-12 for c in p[0]["duu"]), "a plane has no second derivatives")
