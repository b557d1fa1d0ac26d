// Request budgets. Checked in api/ before any geometry work starts (STYLE d.3: never trust input sizes):
// subdivision multiplies the face count by 4 per level, so a 2-face mesh at level 12 is already 33M faces.
// The server fills these from its command line (`surfaced serve --max-body-mb ... --max-grid-cells ...`; the budget
// flags are in server/cli/limit_flags.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

namespace surfaced::api {

struct Limits {
    //! Largest request body accepted, in bytes. Over it: 413 payload_too_large (the HTTP layer enforces the same
    //! number with set_payload_max_length, so the body is never buffered in full).
    std::size_t max_body_bytes = std::size_t{64} << 20;
    //! Largest `levels` for subdivision. Over it: 422 budget_exceeded, field "levels".
    int max_levels = 8;
    //! Largest input mesh (after decoding). Over it: 422 budget_exceeded.
    std::uint64_t max_input_faces = 2'000'000;
    std::uint64_t max_input_vertices = 4'000'000;
    //! Largest predicted output (predicted_face_count). Over it: 422 budget_exceeded, before any refinement.
    std::uint64_t max_output_faces = 4'000'000;
    //! Bézier patches (POST /tessellate, GET /patches/...): most patches in one request, and most segments along
    //! one direction of one patch (a tolerance needing more is 422 budget_exceeded, field "tolerance"). The
    //! predicted triangle count is checked against max_output_faces before tessellating.
    std::uint64_t max_patches = 100'000;
    int max_patch_segments = 256;
    //! Implicit surfaces (POST /implicit/mesh, /implicit/query, /pointcloud sampling). Meshing grid cells
    //! (resolution^3, or the finest level of the adaptive mode) are checked before any field is evaluated.
    std::uint64_t max_grid_cells = std::uint64_t{256} * 256 * 256;
    std::uint64_t max_scene_nodes = 10'000;       //!< nodes in one scene DAG (after expanding nothing: refs count once)
    std::uint64_t max_expression_nodes = 10'000;  //!< nodes of one algebraic expression tree
    int max_expression_depth = 64;                //!< nesting depth of one expression
    int max_fractal_iterations = 64;              //!< Mandelbulb / Menger iterations
    std::uint64_t max_level_set_samples = std::uint64_t{256} * 256 * 256;  //!< uploaded level-set grid values
    std::uint64_t max_query_points = 1'000'000;                            //!< points + rays in one /implicit/query
    int max_ray_steps = 10'000;                                            //!< sphere-tracing steps per ray
    //! POST /mesh/query: points + rays in one request, and the point-triangle terms of exact winding numbers
    //! (points x triangles with winding.exact; the hierarchy needs ~log F per point and has no such bound).
    std::uint64_t max_mesh_queries = 1'000'000;
    std::uint64_t max_exact_winding_work = 1'000'000'000;
    //! Points in one point cloud (input or sampled output). Normal orientation keeps a kNN graph of ~190 bytes a point
    //! (k = 16), so 2M points stay under ~400 MB.
    std::uint64_t max_points = 2'000'000;
    //! POST /reconstruct: the largest octree depth, and the largest predicted peak memory (estimate_poisson: octree,
    //! solver, samples and the extraction's tables), in bytes. Over either: 422 budget_exceeded naming "depth". The
    //! finest grid, (2^depth)^3 cells, is also held to max_grid_cells.
    int max_reconstruct_depth = 10;
    std::uint64_t max_reconstruct_bytes = std::uint64_t{1} << 30;
    //! POST /limit/evaluate: (face, u, v) points in one request (each answer is about 10 vectors).
    std::uint64_t max_limit_points = 1'000'000;
    //! Per-request compute deadline in milliseconds (0: none). Long work polls a surfaced::Cancel and stops with
    //! 503 when it passes.
    std::uint64_t compute_deadline_ms = 0;
};

}  // namespace surfaced::api
