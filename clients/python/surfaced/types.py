"""Types of the surfaced API's requests and answers, as in its OpenAPI document (api/openapi.json).

Enumerations are ``Literal`` aliases and JSON objects are ``TypedDict`` classes, so that a type checker catches a
misspelt option value or member. Implicit scenes are plain dictionaries (``{"op": "sphere", "radius": 1}``): their
node types are listed in the OpenAPI document's ``ImplicitScene`` schema and in docs/implicit.md.
"""
from __future__ import annotations

from typing import Any, Dict, List, Literal, Sequence, TypedDict, Union

__all__ = [
    "Vec2", "Vec3", "Point", "Bounds", "ImplicitScene",
    "Scheme", "Boundary", "CreaseMethod", "TriangleRule", "UvInterpolation", "LoopWeights", "OutputFormat",
    "Compression", "RepairMode", "RemeshSmoothing", "ImplicitMode", "TessellateFormat", "PatchSampleFormat",
    "PointcloudFormat", "CurvesFormat", "KnotVector", "PoissonBoundary", "NormalEstimation",
    "Mesh", "Output", "Crease", "Corner", "LimitPoint", "Patch", "Ray", "EstimateNormals", "Sample", "Derivatives", "Tolerance",
    "ChainPiece", "Chain", "BSpline", "Continuity", "EnforceC1", "InsertKnot", "CurvesOutput", "JsonValue",
    "BSplineSurface", "SurfaceInsertKnot", "SurfaceElevate",
]

Vec2 = Sequence[float]
Vec3 = Sequence[float]
#: a 2D or 3D point of a curve
Point = Sequence[float]
#: [[xmin, ymin, zmin], [xmax, ymax, zmax]]
Bounds = Sequence[Vec3]
#: a node of an implicit scene ({"op": ..., ...}); nodes nest through "arg" / "args"
ImplicitScene = Dict[str, Any]

Scheme = Literal["catmull-clark", "loop"]
Boundary = Literal["edge-only", "edge-and-corner", "none"]
CreaseMethod = Literal["uniform", "chaikin"]
TriangleRule = Literal["catmark", "smooth"]
UvInterpolation = Literal["none", "corners-only", "corners-plus1", "corners-plus2", "boundaries", "all"]
LoopWeights = Literal["loop", "warren"]
OutputFormat = Literal["glb", "gltf", "obj", "ply", "json", "stl", "off"]
Compression = Literal["draco", "none"]
RepairMode = Literal["auto", "none"]
RemeshSmoothing = Literal["tangential", "laplacian", "none"]
ImplicitMode = Literal["uniform", "adaptive"]
TessellateFormat = Literal["glb", "gltf", "obj", "ply", "json", "stl", "off", "patches"]
PatchSampleFormat = Literal["glb", "gltf", "obj", "ply", "json", "stl", "off", "patches"]
PointcloudFormat = Literal["glb", "gltf", "ply", "json"]
CurvesFormat = Literal["json", "glb", "gltf"]
KnotVector = Literal["clamped", "uniform", "closed"]
PoissonBoundary = Literal["neumann", "dirichlet"]
NormalEstimation = Literal["auto", "always", "never"]


class _MeshRequired(TypedDict):
    positions: Sequence[Vec3]
    faces: Sequence[Sequence[int]]


class Mesh(_MeshRequired, total=False):
    """A polygon mesh: positions, faces (vertex indices, 3 or more per face), optional vertex normals (one per
    position, as the JSON output writes them), optional UVs with one UV index per face corner."""
    normals: Sequence[Vec3]
    uvs: Sequence[Vec2]
    uv_faces: Sequence[Sequence[int]]


class Output(TypedDict, total=False):
    """Output options of a JSON request (the ``output`` member); a raw file upload sends them as query parameters.
    Which formats an operation writes, and its defaults, are in that operation's docstring."""
    format: str
    compression: Compression
    quantize_position: int
    normals: bool


class Crease(TypedDict):
    edge: Sequence[int]
    #: 10 or more is infinitely sharp
    sharpness: float


class Corner(TypedDict):
    vertex: int
    sharpness: float


class LimitPoint(TypedDict):
    """A parametric point of POST /limit/evaluate: a base face and (u, v) in its domain (OpenSubdiv Bfr's: [0, 1]^2
    on a quad; an N-gon's N quad sub-face tiles [x, x + 1/2] x [y, y + 1/2])."""
    face: int
    uv: Sequence[float]


class _PatchRequired(TypedDict):
    degree: Sequence[int]
    points: Sequence[Vec3]


class Patch(_PatchRequired, total=False):
    """A tensor-product Bezier patch: degree [m, n], (m+1)(n+1) control points with u varying fastest, and optional
    weights, one per control point (a rational patch; the points stay Euclidean)."""
    weights: Sequence[float]


class Ray(TypedDict):
    origin: Vec3
    direction: Vec3


class EstimateNormals(TypedDict, total=False):
    #: neighbours for the PCA normals, 3..256 (default 16)
    k: int


class _SampleRequired(TypedDict):
    count: int


class Sample(_SampleRequired, total=False):
    """Points sampled area-uniformly on ``mesh``, or on the zero set of ``scene`` within ``bounds``."""
    mesh: Mesh
    scene: ImplicitScene
    bounds: Bounds
    seed: int


class Derivatives(TypedDict):
    t: Sequence[float]
    order: int


class Tolerance(TypedDict):
    tolerance: float


class _ChainPieceRequired(TypedDict):
    points: Sequence[Point]


class ChainPiece(_ChainPieceRequired, total=False):
    weights: Sequence[float]


class _ChainRequired(TypedDict):
    pieces: Sequence[ChainPiece]


class Chain(_ChainRequired, total=False):
    closed: bool


class _BSplineRequired(TypedDict):
    degree: int
    points: Sequence[Point]


class BSpline(_BSplineRequired, total=False):
    weights: Sequence[float]
    knots: Sequence[float]
    knot_vector: KnotVector


class Continuity(TypedDict, total=False):
    position_tolerance: float
    angle_tolerance: float
    derivative_tolerance: float


class EnforceC1(TypedDict, total=False):
    mode: Literal["C1", "G1"]
    side: Literal["left", "right", "both"]
    joints: Sequence[int]


class _InsertKnotRequired(TypedDict):
    u: float


class InsertKnot(_InsertKnotRequired, total=False):
    times: int


class _BSplineSurfaceRequired(TypedDict):
    degree: Sequence[int]
    knots_u: Sequence[float]
    knots_v: Sequence[float]
    points: Sequence[Vec3]


class BSplineSurface(_BSplineSurfaceRequired, total=False):
    """A B-spline/NURBS surface: [p, q] degrees, knot vectors, count_u x count_v control points (u varying fastest),
    optional weights."""
    weights: Sequence[float]


class _SurfaceInsertKnotRequired(TypedDict):
    direction: Literal["u", "v"]
    value: float


class SurfaceInsertKnot(_SurfaceInsertKnotRequired, total=False):
    times: int


class _SurfaceElevateRequired(TypedDict):
    direction: Literal["u", "v"]


class SurfaceElevate(_SurfaceElevateRequired, total=False):
    times: int


class CurvesOutput(TypedDict, total=False):
    format: CurvesFormat
    compression: Literal["none"]


# JSON answers are returned as parsed by the json module
JsonValue = Union[Dict[str, Any], List[Any], str, int, float, bool, None]
