"""POST /subdivide: a cube, Catmull-Clark, 2 levels, as JSON (counts) and as a Draco GLB file; an OBJ upload with
Loop; and a bad request, whose error names the field."""
import os

from _common import OUT, check, client
from surfaced import SurfacedError

cube = {
    "positions": [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1], [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]],
    "faces": [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
}
r = client.subdivide(cube, scheme="catmull-clark", levels=2, output={"format": "json"})
stats = r.json["stats"]
check(stats["output_faces"] == 6 * 4 ** 2, f"cube, 2 levels: {stats['output_faces']} faces")

glb = client.subdivide(cube, levels=3, creases=[{"edge": [0, 1], "sharpness": 2}])
path = os.path.join(OUT, "cube-l3.glb")
glb.save(path)
check(glb.body[:4] == b"glTF", f"GLB written to {path} ({len(glb.body)} bytes, {glb.header('X-Output-Faces')} faces)")

tetra_obj = b"v 1 1 1\nv -1 -1 1\nv -1 1 -1\nv 1 -1 -1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n"
obj = client.subdivide(data=tetra_obj, content_type="model/obj", scheme="loop", levels=2, output={"format": "obj"})
faces = sum(1 for line in obj.body.decode().splitlines() if line.startswith("f "))
check(faces == 4 * 4 ** 2, f"OBJ upload, Loop 2 levels: {faces} faces")

try:
    client.subdivide(cube, levels=2, scheme="butterfly")
    check(False, "an unknown scheme must be refused")
except SurfacedError as e:
    check(e.status == 400 and e.field == "scheme", f"unknown scheme refused: {e}")
