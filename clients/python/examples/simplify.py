"""POST /simplify: a finely tessellated teapot simplified to 10 % with the measured error reported."""
import os

from _common import OUT, check, client

teapot = client.patch_sample("teapot", segments=16, format="obj", normals=False)
r = client.simplify(data=teapot.body, content_type="model/obj", ratio=0.1, report_error=True, output={"format": "obj"})
n_in, n_out = int(r.header("X-Input-Faces")), int(r.header("X-Output-Faces"))
hausdorff = float(r.header("X-Hausdorff"))
check(n_out < 0.15 * n_in, f"{n_in} -> {n_out} triangles (ratio 0.1)")
check(0 < hausdorff < 0.5, f"measured Hausdorff distance {hausdorff:.4g} (teapot is ~6 units wide)")
r.save(os.path.join(OUT, "teapot-10pc.obj"))
