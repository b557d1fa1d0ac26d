"""A client for the surfaced HTTP service, standard library only (urllib).

One method per endpoint. Mesh endpoints take either a JSON mesh (``{"positions": [[x, y, z], ...], "faces": [[i, j,
k, ...], ...]}``) or the bytes of a mesh file (OBJ, OFF, PLY, STL, GLB) with its media type; options are keyword
arguments named as in the API. Results carry the body (bytes), the response headers and, for JSON answers, the
parsed document. Error answers (RFC 9457 problem+json) raise :class:`SurfacedError` with the field path or line.

    from surfaced_client import Client
    c = Client("http://127.0.0.1:8080")
    r = c.subdivide(mesh=cube, scheme="catmull-clark", levels=2, output={"format": "json"})
    print(r.json["stats"]["output_faces"])
"""
from __future__ import annotations

import json
import urllib.error
import urllib.parse
import urllib.request
from dataclasses import dataclass, field
from typing import Any, Mapping, Optional

__all__ = ["Client", "Result", "SurfacedError", "MESH_MEDIA_TYPES"]

#: media type for each mesh file extension the service reads
MESH_MEDIA_TYPES = {
    ".obj": "model/obj", ".off": "model/off", ".ply": "application/ply", ".stl": "model/stl",
    ".glb": "model/gltf-binary",
}


class SurfacedError(Exception):
    """A problem+json answer (or a transport failure: status 0)."""

    def __init__(self, status: int, problem: Mapping[str, Any]):
        self.status = status
        self.problem = dict(problem)
        self.code = problem.get("code")
        self.field = problem.get("field")
        self.line = problem.get("line")
        text = f"{problem.get('status', status)} {problem.get('title', 'error')}: {problem.get('detail', '')}"
        if self.field:
            text += f" (field {self.field})"
        if self.line:
            text += f" (line {self.line})"
        super().__init__(text)


@dataclass
class Result:
    status: int
    content_type: str
    body: bytes
    headers: Mapping[str, str] = field(default_factory=dict)

    @property
    def json(self) -> Any:
        """The parsed body of a JSON answer."""
        return json.loads(self.body)

    def header(self, name: str, default: Optional[str] = None) -> Optional[str]:
        for key, value in self.headers.items():
            if key.lower() == name.lower():
                return value
        return default

    def save(self, path: str) -> None:
        with open(path, "wb") as f:
            f.write(self.body)


def _query_value(value: Any) -> str:
    return ("true" if value else "false") if isinstance(value, bool) else str(value)


class Client:
    def __init__(self, base_url: str = "http://127.0.0.1:8080", timeout: float = 60.0):
        self.base_url = base_url.rstrip("/")
        self.timeout = timeout

    # -- transport -------------------------------------------------------------------------------------------------
    def request(self, method: str, path: str, *, json_body: Any = None, data: Optional[bytes] = None,
                content_type: Optional[str] = None, query: Optional[Mapping[str, Any]] = None,
                headers: Optional[Mapping[str, str]] = None) -> Result:
        url = self.base_url + path
        if query:
            url += "?" + urllib.parse.urlencode({k: _query_value(v) for k, v in query.items() if v is not None})
        hdrs = dict(headers or {})
        if json_body is not None:
            data = json.dumps(json_body).encode()
            content_type = "application/json"
        if content_type:
            hdrs["Content-Type"] = content_type
        req = urllib.request.Request(url, data=data, method=method, headers=hdrs)
        try:
            with urllib.request.urlopen(req, timeout=self.timeout) as res:
                return Result(res.status, res.headers.get("Content-Type", ""), res.read(), dict(res.headers.items()))
        except urllib.error.HTTPError as e:
            body = e.read()
            if e.code == 304:
                return Result(304, "", body, dict(e.headers.items()))
            try:
                problem = json.loads(body)
            except ValueError:
                problem = {"title": e.reason, "detail": body[:300].decode(errors="replace")}
            raise SurfacedError(e.code, problem) from None
        except urllib.error.URLError as e:
            raise SurfacedError(0, {"title": "connection failed", "detail": f"{url}: {e.reason}"}) from None

    def _mesh_operation(self, path: str, mesh: Any, data: Optional[bytes], content_type: Optional[str],
                        options: Mapping[str, Any]) -> Result:
        if (mesh is None) == (data is None):
            raise ValueError("give either mesh (JSON) or data (file bytes) with content_type")
        if mesh is not None:
            return self.request("POST", path, json_body={"mesh": mesh, **options})
        # raw file: options go in the query; "output" sub-options are flattened there (format, compression, ...)
        query = {k: v for k, v in options.items() if k != "output"}
        query.update(options.get("output", {}))
        return self.request("POST", path, data=data, content_type=content_type or "application/octet-stream", query=query)

    # -- endpoints -------------------------------------------------------------------------------------------------
    def healthz(self) -> dict:
        """GET /healthz."""
        return self.request("GET", "/healthz").json

    def openapi(self) -> dict:
        """GET /openapi.json: the OpenAPI 3.1 document."""
        return self.request("GET", "/openapi.json").json

    def subdivide(self, mesh: Any = None, *, data: Optional[bytes] = None, content_type: Optional[str] = None,
                  **options: Any) -> Result:
        """POST /subdivide. Options: scheme, levels, boundary, creases, corners, holes, limit_surface, ..., output."""
        return self._mesh_operation("/subdivide", mesh, data, content_type, options)

    def simplify(self, mesh: Any = None, *, data: Optional[bytes] = None, content_type: Optional[str] = None,
                 **options: Any) -> Result:
        """POST /simplify. Options: target_faces, ratio, max_error, lock_border, restore_volume, threads,
        locked_vertices, report_error, repair ("auto" | "none"), output. What repair did: header X-Repairs."""
        return self._mesh_operation("/simplify", mesh, data, content_type, options)

    def tessellate(self, patches: Any = None, *, bez: Optional[str] = None, **options: Any) -> Result:
        """POST /tessellate: JSON patches ([{"degree": [m, n], "points": [...]}]) or geomview BEZ text.
        Options: tolerance or segments, output (JSON form) / format, compression (BEZ form)."""
        if (patches is None) == (bez is None):
            raise ValueError("give either patches or bez")
        if patches is not None:
            return self.request("POST", "/tessellate", json_body={"patches": patches, **options})
        query = {k: v for k, v in options.items() if k != "output"}
        query.update(options.get("output", {}))
        return self.request("POST", "/tessellate", data=bez.encode(), content_type="application/x-geomview-bez",
                            query=query)

    def patch_sample(self, name: str = "teapot", *, etag: Optional[str] = None, **query: Any) -> Result:
        """GET /patches/{name}: a built-in sample tessellated (tolerance | segments, format, ...); format="json" gives
        its control points. With etag, an unchanged answer is a Result with status 304."""
        headers = {"If-None-Match": etag} if etag else None
        return self.request("GET", "/patches/" + urllib.parse.quote(name, safe=""), query=query, headers=headers)

    def curves(self, points: Any, **queries: Any) -> dict:
        """POST /curves: evaluate, derivatives, curvature, split, elevate, bounding_box, length, closest, tessellate."""
        return self.request("POST", "/curves", json_body={"points": points, **queries}).json

    def remesh(self, mesh: Any = None, *, data: Optional[bytes] = None, content_type: Optional[str] = None,
               **options: Any) -> Result:
        """POST /remesh: isotropic remeshing. Options: edge_length, iterations, feature_angle, keep_boundary,
        smoothing, repair ("auto" | "none"), output. Quality before/after comes in the X-Min-Angle-*, X-Below-30-*
        headers, what repair did in X-Repairs."""
        return self._mesh_operation("/remesh", mesh, data, content_type, options)

    def repair(self, mesh: Any = None, *, data: Optional[bytes] = None, content_type: Optional[str] = None,
               **options: Any) -> Result:
        """POST /repair: weld, drop degenerate and duplicate faces, orient, cut non-manifold edges and vertices apart.
        Options: weld_tolerance, orient, min_component_faces, max_hole_edges, output. The report: header X-Repairs,
        and stats["repairs"] of the JSON form."""
        return self._mesh_operation("/repair", mesh, data, content_type, options)

    def implicit_query(self, scene: Any, **queries: Any) -> dict:
        """POST /implicit/query: points (classified and evaluated), rays (first hit), tolerance, max_distance,
        max_steps."""
        return self.request("POST", "/implicit/query", json_body={"scene": scene, **queries}).json

    def implicit_mesh(self, scene: Any, bounds: Any, **options: Any) -> Result:
        """POST /implicit/mesh: the zero level set of a scene inside bounds ([[x0,y0,z0],[x1,y1,z1]]) as a closed
        triangle mesh. Options: resolution | cell_size, mode ("uniform" | "adaptive"), simplify_tolerance, output."""
        return self.request("POST", "/implicit/mesh", json_body={"scene": scene, "bounds": bounds, **options})

    def pointcloud(self, points: Any = None, *, data: Optional[bytes] = None, content_type: Optional[str] = None,
                   **options: Any) -> Result:
        """POST /pointcloud: points (JSON, with optional normals/colors), or a PLY/OBJ/XYZ file, or sample={mesh |
        scene + bounds, count, seed}; estimate_normals (true or {"k": n}); output (format glb, ply or json)."""
        if data is not None:
            query = {k: v for k, v in options.items() if k != "output"}
            query.update(options.get("output", {}))
            return self.request("POST", "/pointcloud", data=data, content_type=content_type or "application/octet-stream",
                                query=query)
        body = dict(options)
        if points is not None:
            body["points"] = points
        return self.request("POST", "/pointcloud", json_body=body)
