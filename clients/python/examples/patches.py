"""GET /patches/teapot (tessellated, ETag/304, control points) and POST /tessellate with edited control points."""
import os

from _common import OUT, check, client

glb = client.patch_sample("teapot", tolerance=0.01)
glb.save(os.path.join(OUT, "teapot.glb"))
check(glb.body[:4] == b"glTF", f"teapot within 0.01: error bound {glb.header('X-Error-Bound')}")
again = client.patch_sample("teapot", tolerance=0.01, etag=glb.header("ETag"))
check(again.status == 304, "unchanged sample answers 304 Not Modified")

net = client.patch_sample("teapot", format="patches").json
check(len(net["patches"]) == 32, "teapot control points: 32 bicubic patches")
original = client.patch_sample("teapot", segments=4, format="obj")
net["patches"][0]["points"][5][2] += 0.5   # lift one interior control point of the first patch
r = client.tessellate(net["patches"], segments=4, output={"format": "obj"})
check(r.header("X-Output-Faces") == original.header("X-Output-Faces") and r.body != original.body,
      f"edited patches tessellated: {r.header('X-Output-Faces')} triangles (as before), new positions, "
      f"{r.header('X-Elapsed-Ms')} ms on the server")
r.save(os.path.join(OUT, "teapot-edited.obj"))

bez = "BEZ113\n0 0 0  1 0 0\n0 1 0  1 1 1\n"   # one bilinear patch (degree 1 x 1) in geomview BEZ
flat = client.tessellate(bez=bez, segments=2, format="obj")
check(int(flat.header("X-Output-Faces")) == 8, "a BEZ bilinear patch at 2 segments: 8 triangles")
