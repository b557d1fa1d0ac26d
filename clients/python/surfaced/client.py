"""The HTTP client: :class:`Client` (one method per endpoint), :class:`Result` and the errors.

Options are keyword-only and named as in the API. Their defaults in the signatures are the API's documented defaults;
an option left at its default is not sent (the server applies the same default), ``None`` means "not given" (the
server decides). The flattened output options (``format``, ``compression``, ``quantize_position``, ``normals``) and
the ``output`` mapping are interchangeable: a JSON request gets them in ``output``, a file upload as query parameters.
"""
from __future__ import annotations

import json
import re
import urllib.error
import urllib.parse
import urllib.request
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Dict, Mapping, NamedTuple, Optional, Sequence, Tuple, Union

from ._version import API_VERSION
from .types import (
    Boundary, Bounds, BSpline, BSplineSurface, Chain, Compression, Continuity, Corner, Crease, CreaseMethod,
    CurvesOutput, Derivatives, EnforceC1, EstimateNormals, ImplicitMode, ImplicitScene, InsertKnot, LimitPoint,
    LoopWeights, Mesh, NormalEstimation, Output, OutputFormat, Patch, PatchSampleFormat, Point, PointcloudFormat,
    PoissonBoundary, Ray, RemeshSmoothing, RepairMode, Sample, Scheme, SurfaceElevate, SurfaceInsertKnot, TessellateFormat,
    TessellateSurface, Tolerance, TriangleRule, UvInterpolation, Vec2, Vec3,
)

if TYPE_CHECKING:  # numpy is optional: only the array helpers need it
    import numpy
    import numpy.typing

__all__ = [
    "Client", "Result", "SurfacedError", "IncompatibleServerError", "PointArrays", "MESH_MEDIA_TYPES",
    "is_compatible",
]

#: media type for each mesh file extension the service reads
MESH_MEDIA_TYPES: Dict[str, str] = {
    ".obj": "model/obj", ".off": "model/off", ".ply": "application/ply", ".stl": "model/stl",
    ".glb": "model/gltf-binary", ".gltf": "model/gltf+json",
}

_OUTPUT_KEYS = ("format", "compression", "quantize_position", "normals")


class SurfacedError(Exception):
    """A problem+json answer (RFC 9457), or a transport failure (status 0). ``field`` names the request member that
    is wrong (``mesh.faces[3][1]``), ``line`` the line of an uploaded file, ``hint`` what would make the request work
    ("repair=auto repairs it")."""

    def __init__(self, status: int, problem: Mapping[str, Any]) -> None:
        self.status: int = status
        self.problem: Dict[str, Any] = dict(problem)
        self.code: Optional[str] = problem.get("code")
        self.field: Optional[str] = problem.get("field")
        self.line: Optional[int] = problem.get("line")
        self.hint: Optional[str] = problem.get("hint")
        text = f"{problem.get('status', status)} {problem.get('title', 'error')}: {problem.get('detail', '')}"
        if self.field:
            text += f" (field {self.field})"
        if self.line:
            text += f" (line {self.line})"
        if self.hint:
            text += f" (hint: {self.hint})"
        super().__init__(text)


class IncompatibleServerError(Exception):
    """The server implements an API version this client was not made for (see :func:`is_compatible`)."""

    def __init__(self, server_version: str, api_version: str = API_VERSION) -> None:
        self.server_version = server_version
        self.api_version = api_version
        super().__init__(f"the server implements API {server_version}; this client was made for {api_version}")


def _version_tuple(version: str) -> Tuple[int, int, int]:
    match = re.match(r"\s*v?(\d+)(?:\.(\d+))?(?:\.(\d+))?", version)
    if not match:
        raise ValueError(f"not a version: {version!r}")
    return int(match.group(1)), int(match.group(2) or 0), int(match.group(3) or 0)


def is_compatible(server_version: str, client_version: str = API_VERSION) -> bool:
    """Whether a server implementing API ``server_version`` serves a client made for ``client_version``, by semantic
    versioning: the same major version and a minor version at least the client's (the server may have added
    options); before 1.0, the same minor version."""
    server, client = _version_tuple(server_version), _version_tuple(client_version)
    if server[0] != client[0]:
        return False
    if server[0] == 0:
        return server[1] == client[1]
    return server[1] >= client[1]


class PointArrays(NamedTuple):
    """A JSON point cloud as arrays: points (N, 3) float64; normals (N, 3) and colors (N, 3 or 4) or None."""
    points: "numpy.typing.NDArray[numpy.float64]"
    normals: "Optional[numpy.typing.NDArray[numpy.float64]]"
    colors: "Optional[numpy.typing.NDArray[numpy.float64]]"


def _numpy() -> Any:
    try:
        import numpy
    except ImportError:
        raise ImportError("the array helpers need numpy (pip install numpy, or apt-get install python3-numpy)") \
            from None
    return numpy


@dataclass
class Result:
    """An answer: status, media type, the body as bytes and the response headers (look them up with
    :meth:`header`, case-insensitively)."""
    status: int
    content_type: str
    body: bytes
    headers: Mapping[str, str] = field(default_factory=dict)

    @property
    def json(self) -> Any:
        """The parsed body of a JSON answer."""
        return json.loads(self.body)

    def text(self) -> str:
        """The body as UTF-8 text (OBJ, PLY ascii, glTF JSON, metrics)."""
        return self.body.decode("utf-8")

    def header(self, name: str, default: Optional[str] = None) -> Optional[str]:
        """A response header (``X-Output-Faces``, ``X-Repairs``, ``ETag``, ...), case-insensitively."""
        for key, value in self.headers.items():
            if key.lower() == name.lower():
                return value
        return default

    def save(self, path: str) -> None:
        """Writes the body to a file."""
        with open(path, "wb") as f:
            f.write(self.body)

    def _json_document(self, what: str) -> Any:
        if not self.content_type.startswith("application/json"):
            raise ValueError(f"{what} needs a JSON answer (format json); this one is {self.content_type or 'empty'}")
        return self.json

    def mesh_arrays(self) -> "Tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.int64]]":
        """The mesh of a JSON answer (``format="json"``) as numpy arrays: positions (N, 3) float64 and faces (M, k)
        int64, k the corners per face. Faces of different sizes (a polygon mesh that is not all triangles or all
        quads) raise ValueError: read ``result.json["mesh"]["faces"]`` then. Needs numpy."""
        np = _numpy()
        doc = self._json_document("mesh_arrays()")
        mesh = doc.get("mesh", doc) if isinstance(doc, dict) else None
        if not isinstance(mesh, dict) or "positions" not in mesh or "faces" not in mesh:
            raise ValueError("this answer has no mesh")
        positions = np.asarray(mesh["positions"], dtype=np.float64).reshape(-1, 3)
        faces = mesh["faces"]
        sizes = {len(f) for f in faces}
        if len(sizes) > 1:
            raise ValueError(f"faces of {sorted(sizes)} corners do not make one array; use json['mesh']['faces']")
        corners = sizes.pop() if sizes else 3
        return positions, np.asarray(faces, dtype=np.int64).reshape(-1, corners)

    def point_arrays(self) -> PointArrays:
        """The point cloud of a JSON answer of :meth:`Client.pointcloud` (``format="json"``) as numpy arrays. Needs
        numpy."""
        np = _numpy()
        doc = self._json_document("point_arrays()")
        if not isinstance(doc, dict) or "points" not in doc:
            raise ValueError("this answer has no points")

        def optional(key: str) -> Any:
            value = doc.get(key)
            return np.asarray(value, dtype=np.float64) if value else None

        return PointArrays(np.asarray(doc["points"], dtype=np.float64).reshape(-1, 3), optional("normals"),
                           optional("colors"))


def _query_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):   # locked_vertices=[0, 5] -> "0,5"
        return ",".join(_query_value(v) for v in value)
    return str(value)


def _same(value: Any, default: Any) -> bool:
    return isinstance(value, bool) == isinstance(default, bool) and value == default


def _options(args: Mapping[str, Any], defaults: Mapping[str, Any], skip: Sequence[str]) -> Dict[str, Any]:
    """The options given: not None, and not equal to a documented default (which the server applies anyway)."""
    out: Dict[str, Any] = {}
    for key, value in args.items():
        if key in skip or key == "self" or value is None:
            continue
        default = defaults.get(key)
        if default is not None and _same(value, default):
            continue
        out[key] = value
    return out


def _take_output(options: Dict[str, Any], output: Optional[Mapping[str, Any]]) -> Dict[str, Any]:
    """Moves the flattened output options into a copy of ``output``; a value given both ways must agree."""
    merged = dict(output or {})
    for key in _OUTPUT_KEYS:
        if key in options:
            value = options.pop(key)
            if key in merged and not _same(merged[key], value):
                raise ValueError(f"{key}={value!r} disagrees with output[{key!r}]={merged[key]!r}")
            merged[key] = value
    return merged


def _query(options: Mapping[str, Any], output: Mapping[str, Any]) -> Dict[str, Any]:
    query = dict(options)
    for key, value in query.items():
        if isinstance(value, Mapping) or (isinstance(value, (list, tuple)) and any(
                isinstance(v, (list, tuple, Mapping)) for v in value)):
            raise ValueError(f"{key} can only be sent in a JSON request, not with a file upload")
    query.update(output)
    return query


class Client:
    """A client of one surfaced server.

    ``token`` is sent as ``Authorization: Bearer`` (a server started with a token needs it for everything but the
    probes and /openapi.json); ``headers`` are added to every request.
    """

    def __init__(self, base_url: str = "http://127.0.0.1:8080", timeout: float = 60.0, *,
                 token: Optional[str] = None, headers: Optional[Mapping[str, str]] = None) -> None:
        self.base_url = base_url.rstrip("/")
        self.timeout = timeout
        self.headers: Dict[str, str] = dict(headers or {})
        if token:
            self.headers["Authorization"] = f"Bearer {token}"

    # -- transport -------------------------------------------------------------------------------------------------
    def request(self, method: str, path: str, *, json_body: Any = None, data: Optional[bytes] = None,
                content_type: Optional[str] = None, query: Optional[Mapping[str, Any]] = None,
                headers: Optional[Mapping[str, str]] = None) -> Result:
        """Any request: ``json_body`` is sent as application/json, ``data`` with ``content_type``. An error answer
        raises :class:`SurfacedError`; 304 Not Modified is a Result."""
        url = self.base_url + path
        if query:
            pairs = {k: _query_value(v) for k, v in query.items() if v is not None}
            if pairs:
                url += "?" + urllib.parse.urlencode(pairs)
        hdrs = {**self.headers, **(headers or {})}
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

    def _operation(self, path: str, args: Mapping[str, Any], defaults: Mapping[str, Any], *,
                   payload: Union[str, Tuple[str, ...]], data: Optional[bytes], content_type: Optional[str]) -> Result:
        """POST a JSON request ({payload: ..., options..., output}) or, with ``data``, a file with the options as
        query parameters. ``payload`` may name several members, of which the JSON form needs at least one."""
        payloads = (payload,) if isinstance(payload, str) else payload
        names = " or ".join(payloads)
        options = _options(args, defaults, skip=(*payloads, "data", "content_type", "output"))
        output = _take_output(options, args.get("output"))
        given = {name: args[name] for name in payloads if args.get(name) is not None}
        if data is None:
            if not given:
                raise ValueError(f"give either {names} (JSON) or data (file bytes) with content_type")
            body = {**given, **options}
            if output:
                body["output"] = output
            return self.request("POST", path, json_body=body)
        if given:
            raise ValueError(f"give either {names} (JSON) or data (file bytes), not both")
        return self.request("POST", path, data=data, content_type=content_type or "application/octet-stream",
                            query=_query(options, output))

    # -- version ---------------------------------------------------------------------------------------------------
    def server_version(self) -> str:
        """The API version the server implements: ``info.version`` of its /openapi.json (no probe or header reports
        a version)."""
        return str(self.openapi()["info"]["version"])

    def check_server_version(self) -> str:
        """The server's API version; raises :class:`IncompatibleServerError` when this client was not made for it
        (:func:`is_compatible` with :data:`surfaced.API_VERSION`)."""
        version = self.server_version()
        if not is_compatible(version, API_VERSION):
            raise IncompatibleServerError(version, API_VERSION)
        return version

    # -- probes and documents --------------------------------------------------------------------------------------
    def healthz(self) -> Dict[str, Any]:
        """GET /healthz: ``{"status": "ok"}`` (an alias of /livez)."""
        return self.request("GET", "/healthz").json

    def livez(self) -> Dict[str, Any]:
        """GET /livez: ``{"status": "ok"}`` while the process answers (also while draining)."""
        return self.request("GET", "/livez").json

    def readyz(self) -> Dict[str, Any]:
        """GET /readyz: ``{"status": "ready"}``; a draining server raises SurfacedError 503 (code ``draining``)."""
        return self.request("GET", "/readyz").json

    def metrics(self) -> str:
        """GET /metrics: the Prometheus text exposition (needs the token when the server has one)."""
        return self.request("GET", "/metrics").text()

    def openapi(self) -> Dict[str, Any]:
        """GET /openapi.json: the OpenAPI 3.1 document."""
        return self.request("GET", "/openapi.json").json

    # -- mesh operations -------------------------------------------------------------------------------------------
    def subdivide(self, mesh: Optional[Mesh] = None, *, data: Optional[bytes] = None,
                  content_type: Optional[str] = None,
                  scheme: Scheme = "catmull-clark", levels: int = 1, tolerance: Optional[float] = None,
                  straddle: float = 0.45, target_faces: Optional[int] = None, boundary: Optional[Boundary] = None, crease_method: CreaseMethod = "uniform",
                  triangle_rule: TriangleRule = "catmark", uv_interpolation: UvInterpolation = "corners-plus1",
                  loop_weights: LoopWeights = "loop", limit_surface: bool = False, threads: int = 1,
                  creases: Optional[Sequence[Crease]] = None, corners: Optional[Sequence[Corner]] = None,
                  holes: Optional[Sequence[int]] = None, output: Optional[Output] = None,
                  format: OutputFormat = "glb", compression: Compression = "draco", quantize_position: int = 14,
                  normals: bool = True) -> Result:
        """POST /subdivide: Catmull-Clark or Loop subdivision.

        Input: ``mesh`` (JSON), or ``data``, the bytes of an OBJ (with OpenSubdiv ``t`` tags), OFF, PLY, STL, GLB or
        glTF file, with its ``content_type`` (see MESH_MEDIA_TYPES).

        :param scheme: ``"catmull-clark"`` (default) or ``"loop"`` (triangles only).
        :param levels: refinement levels, 0..8 (default 1).
        :param tolerance: instead of ``levels``: triangles within this distance (model units) of the Catmull-Clark
            limit surface, segments per edge chosen from its curvature; excludes ``levels`` and ``target_faces``.
        :param straddle: with ``tolerance``, 0 to below 1 (default 0.45): vertices move off the limit surface towards
            its convex side by ``straddle`` x ``tolerance`` where it curves one way, so the surface crosses the
            triangles (the distance stays within the tolerance; fewer triangles); 0: every vertex on the surface.
        :param target_faces: use the largest level (up to ``levels``, if given) whose output has at most this many
            faces, at least 1; the server still accepts its deprecated name ``max_faces``.
        :param boundary: ``"edge-only"``, ``"edge-and-corner"`` or ``"none"`` (OpenSubdiv's boundary rules);
            default: the OBJ ``t interpolateboundary`` tag, else edge-only.
        :param crease_method: ``"uniform"`` (default) or ``"chaikin"``.
        :param triangle_rule: Catmull-Clark on triangles: ``"catmark"`` (default) or ``"smooth"``.
        :param uv_interpolation: face-varying UV rule: ``"none"``, ``"corners-only"``, ``"corners-plus1"``
            (default), ``"corners-plus2"``, ``"boundaries"``, ``"all"``.
        :param loop_weights: Loop's vertex weights: ``"loop"`` (default) or ``"warren"``.
        :param limit_surface: project the result onto the limit surface (default False).
        :param threads: 1 (default) or 2: a second thread for large levels and, with ``tolerance``, for half of the
            faces' planning (the same mesh).
        :param creases: JSON only: ``[{"edge": [i, j], "sharpness": s}]`` (10 or more: infinitely sharp).
        :param corners: JSON only: ``[{"vertex": i, "sharpness": s}]``.
        :param holes: JSON only: indices of faces that are holes.
        :param output: ``{"format", "compression", "quantize_position", "normals"}``, or the same as keywords:
        :param format: ``"glb"`` (default), ``"gltf"``, ``"obj"``, ``"ply"``, ``"json"`` (mesh and stats), ``"stl"``
            (binary) or ``"off"``.
        :param compression: GLB/glTF: ``"draco"`` (default) or ``"none"``.
        :param quantize_position: Draco position bits, 1..24 (default 14).
        :param normals: write vertex normals (default True; not with stl or off).
        """
        return self._operation("/subdivide", locals(), Client.subdivide.__kwdefaults__, payload="mesh", data=data,
                               content_type=content_type)

    def simplify(self, mesh: Optional[Mesh] = None, *, data: Optional[bytes] = None,
                 content_type: Optional[str] = None,
                 target_faces: Optional[int] = None, ratio: Optional[float] = None, max_error: Optional[float] = None,
                 lock_border: bool = False, restore_volume: float = 0, threads: int = 1, report_error: bool = False,
                 locked_vertices: Optional[Sequence[int]] = None, repair: RepairMode = "auto",
                 output: Optional[Output] = None, format: OutputFormat = "glb", compression: Compression = "draco",
                 quantize_position: int = 14, normals: bool = True) -> Result:
        """POST /simplify: Garland-Heckbert quadric edge-collapse simplification. At least one of target_faces,
        ratio, max_error; it stops at whichever is reached first.

        Input: ``mesh`` (JSON), or ``data`` (OBJ, OFF, PLY, STL, GLB, glTF bytes) with its ``content_type``.

        :param target_faces: faces to reach, at least 0.
        :param ratio: the share of the input's faces to keep, in (0, 1].
        :param max_error: largest symmetric Hausdorff distance to the input, model units (measured).
        :param lock_border: keep boundary edges (default False).
        :param restore_volume: Lindstrom-Turk volume restoration, 0..1 (default 0).
        :param threads: 1 (default) or 2 (large meshes collapse on two threads at first).
        :param report_error: measure the Hausdorff distance to the input (X-Hausdorff; default False).
        :param locked_vertices: indices of vertices kept in place and never removed.
        :param repair: ``"auto"`` (default: repair a mesh that is not a clean manifold; X-Repairs) or ``"none"``
            (refuse it with 422 non_manifold).
        :param output: ``{"format", "compression", "quantize_position", "normals"}``, or the same as keywords:
        :param format: ``"glb"`` (default), ``"gltf"``, ``"obj"``, ``"ply"``, ``"json"``, ``"stl"`` or ``"off"``.
        :param compression: GLB/glTF: ``"draco"`` (default) or ``"none"``.
        :param quantize_position: Draco position bits, 1..24 (default 14).
        :param normals: write vertex normals (default True; not with stl or off).
        """
        return self._operation("/simplify", locals(), Client.simplify.__kwdefaults__, payload="mesh", data=data,
                               content_type=content_type)

    def remesh(self, mesh: Optional[Mesh] = None, *, data: Optional[bytes] = None,
               content_type: Optional[str] = None,
               edge_length: Optional[float] = None, iterations: int = 10, feature_angle: float = 60,
               lock_border: bool = True, smoothing: RemeshSmoothing = "tangential", repair: RepairMode = "auto",
               output: Optional[Output] = None, format: OutputFormat = "glb", compression: Compression = "draco",
               quantize_position: int = 14, normals: bool = True) -> Result:
        """POST /remesh: Botsch-Kobbelt isotropic remeshing to one edge length. Quality before and after comes in
        the X-Min-Angle-*, X-Below-30-* headers (and ``stats`` of the JSON form), what repair did in X-Repairs.

        Input: ``mesh`` (JSON), or ``data`` (OBJ, OFF, PLY, STL, GLB, glTF bytes) with its ``content_type``.

        :param edge_length: target edge length L, model units; default: the input's mean edge length.
        :param iterations: 0..100 (default 10).
        :param feature_angle: dihedral angle in degrees above which an edge is a sharp feature, 0..180 (default 60;
            180 disables features).
        :param lock_border: boundary vertices stay on the input boundary (default True: moving an open mesh's border
            shrinks it); the server still accepts its deprecated name ``keep_boundary``.
        :param smoothing: ``"tangential"`` (default), ``"laplacian"`` or ``"none"``.
        :param repair: ``"auto"`` (default) or ``"none"``, as for :meth:`simplify`.
        :param output: ``{"format", "compression", "quantize_position", "normals"}``, or the same as keywords:
        :param format: ``"glb"`` (default), ``"gltf"``, ``"obj"``, ``"ply"``, ``"json"``, ``"stl"`` or ``"off"``.
        :param compression: GLB/glTF: ``"draco"`` (default) or ``"none"``.
        :param quantize_position: Draco position bits, 1..24 (default 14).
        :param normals: write vertex normals (default True; not with stl or off).
        """
        return self._operation("/remesh", locals(), Client.remesh.__kwdefaults__, payload="mesh", data=data,
                               content_type=content_type)

    def repair(self, mesh: Optional[Mesh] = None, *, data: Optional[bytes] = None,
               content_type: Optional[str] = None,
               weld_tolerance: float = 0, orient: bool = True, min_component_faces: int = 0, max_hole_edges: int = 0,
               output: Optional[Output] = None, format: OutputFormat = "glb", compression: Compression = "draco",
               quantize_position: int = 14, normals: bool = True) -> Result:
        """POST /repair: weld, drop degenerate and duplicate faces, cut non-manifold edges and vertices apart,
        orient, optionally drop small components and fill small holes. The report: header X-Repairs and
        ``stats["repairs"]`` of the JSON form.

        Input: ``mesh`` (JSON), or ``data`` (OBJ, OFF, PLY, STL, GLB, glTF bytes) with its ``content_type``.

        :param weld_tolerance: also weld vertices closer than this, model units (default 0: identical only).
        :param orient: orient faces consistently per component, outward when closed (default True).
        :param min_component_faces: drop components with fewer faces (default 0: keep all).
        :param max_hole_edges: fill holes of at most this many edges, 0..10000 (default 0: none).
        :param output: ``{"format", "compression", "quantize_position", "normals"}``, or the same as keywords:
        :param format: ``"glb"`` (default), ``"gltf"``, ``"obj"``, ``"ply"``, ``"json"``, ``"stl"`` or ``"off"``.
        :param compression: GLB/glTF: ``"draco"`` (default) or ``"none"``.
        :param quantize_position: Draco position bits, 1..24 (default 14).
        :param normals: write vertex normals (default True; not with stl or off).
        """
        return self._operation("/repair", locals(), Client.repair.__kwdefaults__, payload="mesh", data=data,
                               content_type=content_type)

    # -- patches and curves ----------------------------------------------------------------------------------------
    def tessellate(self, patches: Optional[Sequence[Patch]] = None, *,
                   surfaces: Optional[Sequence[TessellateSurface]] = None, bez: Optional[str] = None,
                   data: Optional[bytes] = None, content_type: Optional[str] = None,
                   tolerance: Optional[float] = None, segments: int = 8, output: Optional[Output] = None,
                   format: TessellateFormat = "glb", compression: Compression = "draco",
                   quantize_position: int = 14, normals: bool = True) -> Result:
        """POST /tessellate: Bezier patches and B-spline/NURBS surfaces to a crack-free triangle mesh.

        Input: JSON ``patches`` (``[{"degree": [m, n], "points": [...], "weights": [...]}]``) and/or ``surfaces``
        (``[{"degree": [p, q], "knots_u": [...], "knots_v": [...], "points": [...], "weights": [...]}]``), or ``bez``,
        the text of a geomview BEZ/BBP file, or ``data``, the bytes of a BEZ file or an OBJ with free-form bezier or
        bspline surfaces, with its ``content_type`` (``application/x-geomview-bez``, ``model/obj``).

        :param tolerance: guaranteed maximum distance between triangles and surface, model units (excludes
            segments).
        :param segments: segments along each direction of every patch, 1..256 (default 8).
        :param output: ``{"format", "compression", "quantize_position", "normals"}``, or the same as keywords:
        :param format: ``"glb"`` (default), ``"gltf"``, ``"obj"``, ``"ply"``, ``"json"``, ``"stl"``, ``"off"``, or
            ``"patches"``: the Bezier patches (surfaces decomposed) as JSON instead of a mesh.
        :param compression: GLB: ``"draco"`` (default) or ``"none"``.
        :param quantize_position: Draco position bits, 1..30 (default 14).
        :param normals: write vertex normals (default True; not with stl or off).
        """
        args = dict(locals())
        if bez is not None:
            if data is not None:
                raise ValueError("give either bez (text) or data (bytes)")
            args["data"], args["content_type"] = bez.encode(), "application/x-geomview-bez"
        args["bez"] = None
        return self._operation("/tessellate", args, Client.tessellate.__kwdefaults__, payload=("patches", "surfaces"),
                               data=args["data"], content_type=args["content_type"])

    def patch_sample(self, name: str = "teapot", *, etag: Optional[str] = None, tolerance: Optional[float] = None,
                     segments: int = 8, format: PatchSampleFormat = "glb", compression: Compression = "draco",
                     quantize_position: int = 14, normals: bool = True) -> Result:
        """GET /patches/{name}: a built-in sample (``teapot``) tessellated, or with ``format="patches"`` its control
        points (``{"patches": [...]}``, the JSON form :meth:`tessellate` takes; no other option applies then).

        :param etag: the ETag of an earlier answer: an unchanged one is a Result with status 304.
        :param tolerance: guaranteed maximum distance between triangles and surface (excludes segments).
        :param segments: segments along each direction of every patch, 1..256 (default 8).
        :param format: ``"glb"`` (default), ``"gltf"``, ``"obj"``, ``"ply"``, ``"json"`` (the JSON mesh), ``"stl"``,
            ``"off"``, or ``"patches"`` (the control points).
        :param compression: GLB: ``"draco"`` (default) or ``"none"``.
        :param quantize_position: Draco position bits, 1..30 (default 14).
        :param normals: write vertex normals (default True; not with stl or off).
        """
        query = _options(locals(), Client.patch_sample.__kwdefaults__, skip=("name", "etag"))
        headers = {"If-None-Match": etag} if etag else None
        return self.request("GET", "/patches/" + urllib.parse.quote(name, safe=""), query=query, headers=headers)

    def curves(self, points: Optional[Sequence[Point]] = None, *, weights: Optional[Sequence[float]] = None,
               chain: Optional[Chain] = None, svg: Optional[str] = None, bspline: Optional[BSpline] = None,
               evaluate: Optional[Sequence[float]] = None, derivatives: Optional[Derivatives] = None,
               curvature: Optional[Sequence[float]] = None, split: Optional[float] = None,
               elevate: Optional[int] = None, bounding_box: Optional[bool] = None,
               length: Optional[Tolerance] = None, closest: Optional[Point] = None,
               tessellate: Optional[Tolerance] = None, continuity: Union[bool, Continuity, None] = None,
               enforce_c1: Optional[EnforceC1] = None, to_bezier: Optional[bool] = None,
               insert_knot: Optional[InsertKnot] = None, output: Optional[CurvesOutput] = None) -> Result:
        """POST /curves: queries on exactly one curve: ``points`` (one Bezier curve, 2D or 3D; ``weights``: rational),
        ``chain`` (``{"pieces": [{"points": ...}], "closed": bool}``), ``svg`` (SVG path data) or ``bspline``
        (``{"degree", "points", "weights", "knots" | "knot_vector"}``). The answer is JSON (``result.json``) with one
        member per query, or with ``output={"format": "glb" | "gltf"}`` the tessellation as glTF line strips.

        :param evaluate: parameters: t in [0, 1] (one curve), s in [0, pieces] (chain, svg), u in the domain (bspline).
        :param derivatives: ``{"t": [...], "order": n}`` (one curve, bspline).
        :param curvature: parameters t in [0, 1] (one curve).
        :param split: split at t in [0, 1] (one curve).
        :param elevate: raise the degree by this much (one curve).
        :param bounding_box: the tight bounding box (one curve, bspline).
        :param length: ``{"tolerance": e}``: the arc length with a guaranteed error bound.
        :param closest: the closest point of the curve to this point (one curve).
        :param tessellate: ``{"tolerance": e}``: a polyline within e of the curve.
        :param continuity: chain, svg: a report per joint (True, or tolerances).
        :param enforce_c1: chain, svg: ``{"mode": "C1" | "G1", "side": ..., "joints": [...]}``.
        :param to_bezier: svg: the Bezier pieces of each subpath; bspline: the pieces and their knot breaks.
        :param insert_knot: bspline: ``{"u": u, "times": n}`` (Boehm).
        :param output: ``{"format": "json" (default) | "glb" | "gltf", "compression": "none"}``.
        """
        body = _options(locals(), {}, skip=())
        return self.request("POST", "/curves", json_body=body)

    def surfaces(self, surface: BSplineSurface, *, evaluate: Optional[Sequence[Vec2]] = None,
                 derivatives: Optional[Sequence[Vec2]] = None, closest: Optional[Sequence[Vec3]] = None,
                 insert_knot: Optional[SurfaceInsertKnot] = None, elevate: Optional[SurfaceElevate] = None,
                 to_bezier: Optional[bool] = None, bounding_box: Optional[bool] = None) -> Result:
        """POST /surfaces: queries on one B-spline/NURBS surface (``{"degree": [p, q], "knots_u", "knots_v",
        "points", "weights"}``); the answer is JSON (``result.json``) with one member per query.

        :param evaluate: ``[u, v]`` in the domain: position, du, dv and the unit normal.
        :param derivatives: ``[u, v]``: position and the partial derivatives to order 2.
        :param closest: points: the global closest point on the surface to each (uv, point, distance).
        :param insert_knot: ``{"direction": "u" | "v", "value": t, "times": k}``: the refined surface.
        :param elevate: ``{"direction": "u" | "v", "times": k}``: the degree-elevated surface.
        :param to_bezier: the Bezier patches (POST /tessellate's ``patches``) and their breaks.
        :param bounding_box: the control hull's box and the tight box.
        """
        body = _options(locals(), {}, skip=())
        return self.request("POST", "/surfaces", json_body=body)

    # -- implicit surfaces -----------------------------------------------------------------------------------------
    def implicit_query(self, scene: ImplicitScene, *, points: Optional[Sequence[Vec3]] = None,
                       rays: Optional[Sequence[Ray]] = None, tolerance: float = 1e-6, max_distance: float = 100,
                       max_steps: int = 1000) -> Result:
        """POST /implicit/query: classify and evaluate ``points`` (inside / on / outside, value, gradient) and cast
        ``rays`` (``[{"origin": [...], "direction": [...]}]``) against a scene; the answer is JSON (``result.json``).

        :param tolerance: \\|f\\| at most this is "on", at least 0 (default 1e-6).
        :param max_distance: how far rays go, > 0 (default 100).
        :param max_steps: ray-marching steps, at least 1 (default 1000).
        """
        body = {"scene": scene, **_options(locals(), Client.implicit_query.__kwdefaults__, skip=("scene",))}
        return self.request("POST", "/implicit/query", json_body=body)

    # -- mesh queries ----------------------------------------------------------------------------------------------
    def mesh_query(self, mesh: Mesh, *, points: Optional[Union[Sequence[Vec3], Dict[str, str]]] = None,
                   rays: Optional[Union[Sequence[Sequence[float]], Dict[str, str]]] = None,
                   want: Optional[Sequence[str]] = None, winding: Optional[Dict[str, Any]] = None,
                   encoding: str = "json") -> Result:
        """POST /mesh/query: for ``points``, inside (winding number >= 1/2), winding number, signed distance (negative
        inside) and closest point with its face; for ``rays`` (``[ox, oy, oz, dx, dy, dz]``), the first hit. The
        answer is JSON (``result.json``).

        :param want: the point answers, some of ``"inside"``, ``"winding_number"``, ``"distance"``, ``"closest"``
            (default: all four).
        :param winding: ``{"exact": bool (default False), "accuracy": beta > 1 (default 2)}``.
        :param encoding: ``"json"`` (default), or ``"float32"`` / ``"float64"``: every answer array comes as base64 of
            packed little-endian values (booleans uint8, faces int32; -1 and NaN for none), e.g.
            ``numpy.frombuffer(base64.b64decode(s), "<f4")``. ``points`` and ``rays`` may be packed the same way:
            ``{"float32": base64}``.
        """
        body = {"mesh": mesh, **_options(locals(), Client.mesh_query.__kwdefaults__, skip=("mesh",))}
        return self.request("POST", "/mesh/query", json_body=body)

    def limit_evaluate(self, mesh: Mesh, points: Union[Sequence[LimitPoint], Dict[str, str]], *,
                       scheme: Scheme = "catmull-clark", boundary: Optional[Boundary] = None,
                       crease_method: CreaseMethod = "uniform", triangle_rule: TriangleRule = "catmark",
                       uv_interpolation: UvInterpolation = "corners-plus1",
                       creases: Optional[Sequence[Crease]] = None, corners: Optional[Sequence[Corner]] = None,
                       holes: Optional[Sequence[int]] = None, derivatives: int = 1, encoding: str = "json") -> Result:
        """POST /limit/evaluate: the exact Catmull-Clark limit surface of ``mesh`` (the surface ``subdivide``
        converges to with the same options and tags) at ``points``, ``[{"face": f, "uv": [u, v]}, ...]``. The answer
        (``result.json``) is ``{"points": [{"position", "du", "dv", "normal", "exact"}, ...]}``, with ``duu``,
        ``duv``, ``dvv`` when ``derivatives`` is 2 and ``uv`` (the limit of the mesh's texture coordinates) when the
        mesh has ``uvs``.

        :param points: the parametric points; or packed, ``{"float32" | "float64": base64}`` of (face, u, v) triples.
        :param boundary: default: ``"edge-only"``.
        :param derivatives: 1 (default) or 2.
        :param encoding: ``"json"`` (default), or ``"float32"`` / ``"float64"``: each answer member comes as one
            base64 array of packed little-endian values (vectors flattened, ``exact`` uint8), e.g.
            ``numpy.frombuffer(base64.b64decode(s), "<f8").reshape(-1, 3)``.
        """
        body = {"mesh": mesh, "points": points,
                **_options(locals(), Client.limit_evaluate.__kwdefaults__, skip=("mesh", "points"))}
        return self.request("POST", "/limit/evaluate", json_body=body)

    def implicit_grid(self, *, mesh: Optional[Mesh] = None, scene: Optional[ImplicitScene] = None,
                      voxel_size: float, band: int = 3, bounds: Optional[Bounds] = None) -> Result:
        """POST /implicit/grid: a narrow-band signed distance grid of ``mesh`` (exact distances within ``band`` voxels,
        signed by the generalized winding number) or of ``scene`` (its values clamped), exactly one of the two. The
        answer (``result.json``) is a level_set scene node, usable as ``scene`` in implicit_mesh and implicit_query.

        :param voxel_size: the grid spacing, > 0 (required).
        :param band: voxels, 1..64 (default 3); nodes beyond it hold +-band * voxel_size.
        :param bounds: ``[[x0, y0, z0], [x1, y1, z1]]``; required with a scene, a mesh's box grown by band + 1
            voxels when absent.
        """
        body = _options(locals(), Client.implicit_grid.__kwdefaults__, skip=())
        return self.request("POST", "/implicit/grid", json_body=body)

    def implicit_mesh(self, scene: ImplicitScene, bounds: Bounds, *, resolution: int = 64,
                      cell_size: Optional[float] = None, mode: ImplicitMode = "uniform",
                      simplify_tolerance: float = 0, crease_angle: float = 40,
                      output: Optional[Output] = None) -> Result:
        """POST /implicit/mesh: the zero level set of ``scene`` inside ``bounds`` (``[[x0, y0, z0], [x1, y1, z1]]``)
        as a closed, manifold triangle mesh (dual marching cubes; sharp edges kept).

        :param resolution: cells along the longest side of the bounds, 2..65536 (default 64; excludes cell_size).
        :param cell_size: cell size in model units instead of a resolution.
        :param mode: ``"uniform"`` (default) or ``"adaptive"`` (skips empty octree blocks; same mesh).
        :param simplify_tolerance: adaptive mode: QEM-simplify to this Hausdorff distance (default 0: none).
        :param crease_angle: GLB/glTF with normals: split normals where faces meet at more than this many degrees,
            0..180 (default 40).
        :param output: ``{"format": "glb" (default) | "gltf" | "obj" | "ply" | "json" | "stl" | "off", "compression":
            "draco" (default) | "none", "quantize_position": 1..24 (default 14), "normals": bool (default True; not
            with stl or off)}``.
        """
        body = {"scene": scene, "bounds": bounds,
                **_options(locals(), Client.implicit_mesh.__kwdefaults__, skip=("scene", "bounds"))}
        return self.request("POST", "/implicit/mesh", json_body=body)

    # -- point clouds ----------------------------------------------------------------------------------------------
    def reconstruct(self, points: Optional[Sequence[Vec3]] = None, *, data: Optional[bytes] = None,
                    content_type: Optional[str] = None, normals: Union[Sequence[Vec3], bool, None] = None,
                    colors: Optional[Sequence[Sequence[float]]] = None, depth: int = 8, point_weight: float = 4,
                    samples_per_node: float = 1.5, boundary: PoissonBoundary = "neumann", scale: float = 1.1,
                    fit_to_samples: bool = True, confidence: bool = False,
                    estimate_normals: NormalEstimation = "auto", k: int = 16, trim: float = 0,
                    island_area: float = 0.001, vertex_colors: Optional[bool] = None, threads: int = 1,
                    output: Optional[Output] = None, format: OutputFormat = "glb", compression: Compression = "draco",
                    quantize_position: int = 14) -> Result:
        """POST /reconstruct: a closed, outward-oriented triangle mesh through a point cloud (screened Poisson
        reconstruction). Counts, the iso-value and the octree size come in the X-* headers (and ``stats`` of the
        JSON form).

        Input: JSON ``points`` (with optional ``normals``, one per point, pointing out of the solid, and ``colors``),
        or ``data``, a PLY, OBJ, XYZ, GLB or glTF file with its ``content_type`` (``application/ply``,
        ``model/obj``, ``text/x-xyz``, ``model/gltf-binary``, ``model/gltf+json``).

        :param normals: with JSON ``points``: their normals (a list); a bool is the output option: False leaves
            vertex normals out of the mesh (default: written).
        :param depth: finest octree level, 2..10 (default 8): 2^depth cells across the bounding cube; the server's
            grid-cell budget refuses 9 and 10 by default.
        :param point_weight: screening weight, >= 0 (default 4; 0: unscreened).
        :param samples_per_node: samples per cell on a point's splatting level, > 0 (default 1.5).
        :param boundary: ``"neumann"`` (default) or ``"dirichlet"``.
        :param scale: bounding cube side over the points' bounding box's largest side, 1..100 (default 1.1).
        :param fit_to_samples: move each vertex onto the points' tangent planes after meshing (default True; False:
            the indicator's iso-surface as meshed).
        :param confidence: weight each point by a PLY file's confidence property, else its normal's length (default
            False).
        :param estimate_normals: ``"auto"`` (default: when the cloud has none), ``"always"`` or ``"never"``.
        :param k: neighbours for normal estimation, 3..256 (default 16).
        :param trim: cut the surface where the sampling density (octree-depth scale) is below this, >= 0 (default 0:
            keep the closed surface); 0.3 to 1 below the X-Sample-Density header is useful.
        :param island_area: with trim: pieces (and uncut low regions) smaller than this fraction of the area are
            removed (kept), 0..1 (default 0.001).
        :param vertex_colors: carry the points' colours to the vertices (glb, gltf, ply, obj, json); default: when
            the cloud has colours and the format holds them.
        :param threads: 1 (default) or 2: a second thread for the large levels (the same mesh).
        :param output: ``{"format", "compression", "quantize_position", "normals"}``, or the same as keywords:
        :param format: ``"glb"`` (default), ``"gltf"``, ``"obj"``, ``"ply"``, ``"json"``, ``"stl"`` or ``"off"``.
        :param compression: GLB/glTF: ``"draco"`` (default) or ``"none"``.
        :param quantize_position: Draco position bits, 1..24 (default 14).
        """
        args = dict(locals())
        if isinstance(normals, bool):   # the output option; a list is the input's normals (JSON)
            out = dict(output or {})
            if "normals" in out and out["normals"] != normals:
                raise ValueError(f"normals={normals!r} disagrees with output['normals']={out['normals']!r}")
            if not normals:
                out["normals"] = False
            args["output"], args["normals"] = out, None
        return self._operation("/reconstruct", args, Client.reconstruct.__kwdefaults__,
                               payload=("points", "normals", "colors"), data=data, content_type=content_type)

    def pointcloud(self, points: Optional[Sequence[Vec3]] = None, *, data: Optional[bytes] = None,
                   content_type: Optional[str] = None, normals: Union[Sequence[Vec3], bool, None] = None,
                   colors: Optional[Sequence[Sequence[float]]] = None, sample: Optional[Sample] = None,
                   estimate_normals: Union[bool, EstimateNormals] = False, k: int = 16,
                   output: Optional[Output] = None, format: PointcloudFormat = "glb",
                   compression: Compression = "draco", quantize_position: int = 14) -> Result:
        """POST /pointcloud: convert, sample and estimate normals for point clouds.

        Input: JSON ``points`` (with optional ``normals``, one per point, and ``colors``, ``[r, g, b(, a)]`` in 0..1),
        or ``sample`` (``{"count": n, "mesh": ...}`` or ``{"count": n, "scene": ..., "bounds": ..., "seed": s}``),
        or ``data``, a PLY, OBJ, XYZ, GLB or glTF file with its ``content_type`` (``application/ply``,
        ``model/obj``, ``text/x-xyz``, ``model/gltf-binary``, ``model/gltf+json``).

        :param normals: with JSON ``points``: their normals (a list); a bool is the output option: False leaves the
            normals out of the output (default: written).
        :param estimate_normals: replace the normals by PCA of the k nearest neighbours, consistently oriented
            (default False); ``{"k": n}`` also sets k.
        :param k: neighbours for normal estimation, 3..256 (default 16).
        :param output: ``{"format", "compression", "quantize_position", "normals"}``, or the same as keywords:
        :param format: ``"glb"`` (default, one POINTS primitive), ``"gltf"`` (the same as glTF JSON), ``"ply"`` or
            ``"json"``.
        :param compression: GLB: ``"draco"`` (default) or ``"none"``.
        :param quantize_position: Draco position bits, 1..24 (default 14).
        """
        args = dict(locals())
        if isinstance(normals, bool):   # the output option; a list is the input's normals (JSON)
            output = dict(output or {})
            if "normals" in output and output["normals"] != normals:
                raise ValueError(f"normals={normals!r} disagrees with output['normals']={output['normals']!r}")
            if not normals:
                output["normals"] = False
            args["output"], args["normals"] = output, None
        defaults = Client.pointcloud.__kwdefaults__
        if data is None:
            if points is None and sample is None:
                raise ValueError("give points, sample or data (file bytes) with content_type")
            if k != defaults["k"]:   # the JSON form carries k inside estimate_normals
                if not estimate_normals:
                    raise ValueError("k needs estimate_normals")
                args["estimate_normals"] = {**(estimate_normals if isinstance(estimate_normals, dict) else {}),
                                            "k": k}
            options = _options(args, defaults, skip=("data", "content_type", "output", "k", "normals"))
            output_options = _take_output(options, args["output"])
            if args["normals"] is not None:
                options["normals"] = args["normals"]
            if output_options:
                options["output"] = output_options
            return self.request("POST", "/pointcloud", json_body=options)
        if points is not None or sample is not None or args["normals"] is not None or colors is not None:
            raise ValueError("a file upload (data) takes no points, sample, normals list or colors")
        if isinstance(estimate_normals, dict):   # the query form: estimate_normals=true&k=n
            args["estimate_normals"] = True
            args["k"] = estimate_normals.get("k", k)
        options = _options(args, defaults, skip=("data", "content_type", "output", "points"))
        output_options = _take_output(options, args["output"])
        return self.request("POST", "/pointcloud", data=data, content_type=content_type or "application/octet-stream",
                            query=_query(options, output_options))
