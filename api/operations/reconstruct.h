// POST /reconstruct: a closed surface from a point cloud by screened Poisson reconstruction
// (geometry/reconstruct/poisson.h).
//
// Input, as POST /pointcloud takes points: an uploaded point file (PLY, OBJ, XYZ; by Content-Type, sniffed for
// application/octet-stream and text/plain; multipart/form-data with the file as its one file part) with the options
// as query parameters (or form fields), or JSON {"points": [[x,y,z],...], "normals": [...], "colors": [...]} with the
// options as members (output options under "output").
// Options (api/options/catalog.cpp, "reconstruct"): depth, point_weight, samples_per_node, boundary, scale,
// confidence (weights from the normals' lengths: JSON normals are then kept as sent), estimate_normals (auto: when
// the cloud has none; always; never: a cloud without normals is 422 missing_normals) and k, the mesh output options.
// Budgets, before any work: Limits::max_points (the reader's limit, 422 naming "points"), depth <=
// Limits::max_reconstruct_depth, the mesher's grid (2^depth)^3 <= Limits::max_grid_cells and the predicted peak
// bytes (estimate_poisson) <= Limits::max_reconstruct_bytes (each 422 budget_exceeded naming "depth"), points x k for
// normal estimation; the request's Cancel (compute deadline) is polled by the estimation and the reconstruction (503).
// Answer: the mesh (closed, outward) in the requested format, with X-Input-Points, X-Output-Vertices,
// X-Output-Faces, X-Normals-Estimated, X-Iso-Value, X-Octree-Cells, X-Depth and the timing headers.
#pragma once

#include "api/dto.h"
#include "api/operation.h"
#include "geometry/reconstruct/poisson.h"

namespace surfaced::api::operations {

inline constexpr EnumName<PoissonBoundary> kPoissonBoundaryNames[] = {
    {"neumann", PoissonBoundary::Neumann},
    {"dirichlet", PoissonBoundary::Dirichlet},
};

//! When POST /reconstruct estimates normals.
enum class NormalEstimation {
    Auto,    //!< when the cloud has none
    Always,  //!< replace the cloud's own
    Never,   //!< a cloud without normals is refused (422 missing_normals)
};
inline constexpr EnumName<NormalEstimation> kNormalEstimationNames[] = {
    {"auto", NormalEstimation::Auto},
    {"always", NormalEstimation::Always},
    {"never", NormalEstimation::Never},
};

ApiResponse reconstruct(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
