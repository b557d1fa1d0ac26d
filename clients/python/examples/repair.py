"""POST /repair: a bow-tie (two triangles meeting at one vertex), a duplicated triangle and a flipped one, repaired."""
from _common import check, client

mesh = {
    "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [1, 1, 0]],
    "faces": [[0, 1, 2], [0, 3, 4], [0, 1, 2], [2, 5, 1]],
}
r = client.repair(mesh, format="json")
repairs = r.json["stats"]["repairs"]
check(repairs["duplicate"] == 1, f"one duplicate face dropped ({r.header('X-Repairs')})")
check(repairs["nonmanifold_split"] == 1, "the pinched vertex cut apart into two")
check(len(r.json["mesh"]["faces"]) == 3, "3 faces left of 4")
