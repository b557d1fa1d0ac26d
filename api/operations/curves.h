// POST /curves: one curve in one of four forms, and the queries to run on it, answered in JSON (or, for a
// tessellation, as glTF line strips).
//
// Request (application/json): exactly one of "points" (one Bézier curve), "chain", "svg", "bspline".
//  One Bézier curve (2D or 3D, optionally rational):
//   {"points": [[x, y], ...] | [[x, y, z], ...],   all of one dimension; degree = count - 1 (at most kMaxCurveDegree)
//    "weights": [w, ...],                          positive, one per point: a rational curve
//    "evaluate": [t, ...],                         points at parameters in [0, 1]
//    "derivatives": {"t": [t, ...], "order": k},   k-th derivatives (k >= 1)
//    "curvature": [t, ...],
//    "split": t,                                   control points of both halves
//    "elevate": k,                                 control points after raising the degree k times
//    "bounding_box": true,
//    "length": {"tolerance": e},                   arc length and its error bound
//    "closest": [x, y(, z)],                       global closest point: t, point, distance
//    "tessellate": {"tolerance": e}}               polyline within e: points, params, segments, bounds
//  A chain of Bézier pieces (geometry/curves/piecewise.h), or SVG path data (one chain per subpath, 2D):
//   {"chain": {"pieces": [{"points": [...], "weights"?: [...]}, ...], "closed"?: bool} | "svg": "M 0 0 C ...",
//    "continuity": true | {"position_tolerance", "angle_tolerance", "derivative_tolerance"},  per joint, of the input
//    "enforce_c1": {"mode"?: "C1" | "G1", "side"?: "left" | "right" | "both", "joints"?: [i, ...]},
//    "evaluate": [s, ...],                         chain parameters s in [0, pieces]
//    "length": {"tolerance": e}, "tessellate": {"tolerance": e},
//    "to_bezier": true}                            (svg only) the pieces the path data became
//   With enforce_c1, evaluate/length/tessellate (and glTF output) describe the modified chain.
//  A B-spline or NURBS curve (geometry/curves/bspline.h):
//   {"bspline": {"degree": p, "points": [...], "weights"?: [...],
//                "knots"?: [u, ...] | "knot_vector"?: "clamped" (default) | "uniform" | "closed"},
//    "evaluate": [u, ...], "derivatives": {"t": [u, ...], "order": k},   u in the domain [u_p, u_n]
//    "insert_knot": {"u": u, "times"?: k}, "to_bezier": true, "bounding_box": true, "tessellate": {"tolerance": e}}
//  Every form: "output": {"format": "json" (default) | "glb" | "gltf"}. glb/gltf answer with the tessellation only
//  (one LINE_STRIP primitive per polyline; "tessellate" is then required and the other queries refused, no Draco:
//  KHR_draco_mesh_compression covers triangles and points only).
// Response: {"degree", "rational", ...one member per query} (chain: "piece_count", "closed", "rational"; svg:
// "subpaths": [one such object per subpath]; bspline: "degree", "rational", "domain"), points in the input's
// dimension.
// Errors: problem+json with field paths ("points[3][1]", "chain.pieces[2].points[0]", "evaluate[2]",
// "tessellate.tolerance", "bspline.knots"); SVG syntax errors are 422 with field "svg" and the byte offset in the
// path data; 422 budget_exceeded past the budgets below or a tessellation over max_output_faces segments.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "api/dto.h"
#include "api/operation.h"

namespace surfaced::api::operations {

inline constexpr int kMaxCurveDegree = 64;
inline constexpr std::size_t kMaxCurveQueries = 100'000;   //!< parameters in evaluate + derivatives + curvature
                                                           //!< (times the subpaths of an SVG path)
inline constexpr std::size_t kMaxChainPieces = 100'000;    //!< pieces of a chain, or of all subpaths of an SVG path
inline constexpr std::size_t kMaxChainPoints = 1'000'000;  //!< control points of all pieces of a chain
inline constexpr std::size_t kMaxSvgBytes = std::size_t{4} << 20;  //!< length of "svg"
inline constexpr std::size_t kMaxSvgCommands = 200'000;    //!< drawing commands in "svg" (implicit repeats count)
inline constexpr std::size_t kMaxBsplinePoints = 100'000;  //!< control points of a B-spline
inline constexpr int kMaxBsplineDegree = 32;               //!< to_bezier is O(spans p^2), evaluation O(p^2)

ApiResponse curves(const ApiRequest& request, const ApiContext& context) noexcept;

//! Command-line options laid over a request file (`surfaced curve IN.json|IN.svg -o OUT ...`).
struct CurveFileOverrides {
    bool svg = false;                       //!< the file is SVG (a document with <path d="..."> or bare path data)
    std::optional<double> tolerance;        //!< "tessellate": {"tolerance": T}
    bool continuity = false;                //!< "continuity": true
    std::optional<std::string> enforce_c1;  //!< "enforce_c1": {"mode": MODE}
    OutputFormat format = OutputFormat::Json;
};
//! Default tessellation tolerance for glTF output when neither the file nor the overrides give one.
inline constexpr double kDefaultCurveFileTolerance = 1e-3;

//! `file` is a POST /curves body (JSON) or an SVG file; the overrides are merged into the request, which then goes
//! through curves(), so the CLI and the service share one code path. An SVG error names the byte offset and line in
//! the file.
ApiResponse curves_from_file(std::string_view file, const CurveFileOverrides& overrides,
                             const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
