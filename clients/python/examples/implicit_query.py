"""POST /implicit/query: a unit sphere classified at points and hit by a ray (exact signed distance)."""
from _common import check, client

r = client.implicit_query({"op": "sphere", "radius": 1}, points=[[0, 0, 0], [2, 0, 0], [0, 0.6, 0.8]],
                          rays=[{"origin": [-5, 0, 0], "direction": [1, 0, 0]}]).json
classes = [p["class"] for p in r["points"]]
check(classes == ["inside", "outside", "on"], f"classes {classes}")
check(abs(r["points"][0]["value"] + 1) < 1e-9 and abs(r["points"][1]["value"] - 1) < 1e-9, "signed distances -1 and 1")
hit = r["rays"][0]
check(hit["hit"] and abs(hit["t"] - 4) < 1e-3, f"ray from x = -5 hits the sphere at t = {hit.get('t')}")
