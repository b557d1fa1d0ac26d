"""A client for the surfaced HTTP service, standard library only (urllib); numpy optional.

One method per endpoint. Mesh operations take either a JSON mesh (``{"positions": [[x, y, z], ...], "faces": [[i, j,
k, ...], ...]}``) or the bytes of a mesh file (OBJ, OFF, PLY, STL, GLB, glTF) with its media type; options are
keyword-only and named as in the API, with the API's defaults. A :class:`Result` carries the body (bytes), the
response headers and, for JSON answers, the parsed document; with numpy installed, :meth:`Result.mesh_arrays` and
:meth:`Result.point_arrays` give arrays. Error answers (RFC 9457 problem+json) raise :class:`SurfacedError` with the
field path or line.

    import surfaced
    c = surfaced.Client("http://127.0.0.1:8080")
    c.check_server_version()                  # raises IncompatibleServerError for a server of another API version
    r = c.subdivide(cube, scheme="catmull-clark", levels=2, format="json")
    print(r.json["stats"]["output_faces"])
    positions, faces = r.mesh_arrays()        # numpy: (N, 3) float64, (M, 4) int64
"""
from ._version import API_VERSION, __version__
from .client import (
    MESH_MEDIA_TYPES, Client, IncompatibleServerError, PointArrays, Result, SurfacedError, is_compatible,
)
from . import types

__all__ = [
    "API_VERSION", "__version__", "Client", "Result", "SurfacedError", "IncompatibleServerError", "PointArrays",
    "MESH_MEDIA_TYPES", "is_compatible", "types",
]
