// The option tables of the operations (option_spec.h). Ranges here are the ones the readers enforce; the drift test
// holds api/openapi.json to them.
#include <algorithm>
#include <array>
#include <iterator>
#include <vector>

#include "api/dto.h"
#include "api/operations/implicit_mesh.h"
#include "api/operations/reconstruct.h"
#include "api/options/option_spec.h"

namespace surfaced::api::options {
namespace {

constexpr auto kOutputFormats = names_of(kOutputFormatNames);
constexpr auto kCompressions = names_of(kCompressionNames);
constexpr auto kRepairModes = names_of(kRepairModeNames);
constexpr auto kSchemes = names_of(kSchemeNames);
constexpr auto kBoundaries = names_of(kBoundaryNames);
constexpr auto kCreaseMethods = names_of(kCreaseMethodNames);
constexpr auto kTriangleRules = names_of(kTriangleRuleNames);
constexpr auto kUvInterpolations = names_of(kUvInterpolationNames);
constexpr auto kLoopWeights = names_of(kLoopWeightNames);
constexpr auto kSmoothings = names_of(kRemeshSmoothingNames);

constexpr Bound at_least(double v) { return Bound{v, false}; }
constexpr Bound above(double v) { return Bound{v, true}; }
constexpr Bound at_most(double v) { return Bound{v, false}; }
constexpr Bound below(double v) { return Bound{v, true}; }

// ---- the output of the operations that answer with a mesh (JSON: members of "output") ----------------------------
// Each row once; an operation whose encoder offers fewer formats or another default composes its own list from them.
constexpr OptionSpec kFormatOption{
    .name = "format",
    .type = OptionType::Enum,
    .default_json = "\"glb\"",
    .description = "Encoding of the result: binary or text glTF, OBJ, PLY, the JSON mesh, binary STL or OFF",
    .values = kOutputFormats,
    .json_object = "output"};
constexpr OptionSpec kCompressionOption{.name = "compression",
                                        .type = OptionType::Enum,
                                        .default_json = "\"draco\"",
                                        .description = "Draco mesh compression (glTF formats only)",
                                        .values = kCompressions,
                                        .json_object = "output"};
// Draco itself takes up to 30 bits; the glTF writer stops at 24 (geometry/io/gltf_write.cpp kMaxQuantizationBits).
constexpr OptionSpec kQuantizeOption{
    .name = "quantize_position",
    .type = OptionType::Integer,
    .min = at_least(1),
    .max = at_most(24),
    .default_json = "14",
    .units = "bits",
    .description = "Draco position quantization (glTF formats with compression draco only)",
    .json_object = "output"};
// One default on every mesh-producing endpoint. STL and OFF hold no vertex normals: the default does not apply to
// them and true given explicitly is a 400 (request_forms.cpp check_output_options).
constexpr OptionSpec kNormalsOption{
    .name = "normals",
    .type = OptionType::Bool,
    .default_json = "true",
    .description =
        "Write vertex normals (the mesh's own, else computed) in glb, gltf, obj, ply and json; STL has facet "
        "normals only and OFF none, so with stl or off it must be left out or false",
    .json_object = "output"};

constexpr OptionSpec kMeshOutput[] = {kFormatOption, kCompressionOption, kQuantizeOption, kNormalsOption};

constexpr OptionSpec format_of(std::span<const std::string_view> values, std::string_view description) {
    OptionSpec out = kFormatOption;
    out.values = values;
    out.description = description;
    return out;
}
// Every mesh format, and patches: Bézier patches as JSON (the body POST /tessellate takes).
constexpr auto kMeshAndPatchFormats = [] {
    std::array<std::string_view, std::size(kOutputFormatNames) + 1> out{};
    for (std::size_t i = 0; i < std::size(kOutputFormatNames); ++i) out[i] = kOutputFormatNames[i].name;
    out.back() = "patches";
    return out;
}();
// Subdivision: every mesh format, or the limit surface as patches.
constexpr OptionSpec kSubdivideOutput[] = {
    format_of(kMeshAndPatchFormats,
              "Encoding of the result: binary or text glTF, OBJ, PLY, the JSON mesh, binary STL or OFF; or patches: "
              "the limit surface as bicubic Bézier patches (the JSON POST /tessellate takes; Catmull-Clark)"),
    kCompressionOption, kQuantizeOption, kNormalsOption};
// Tessellated patches: every mesh format; the normals written are the patches' exact surface normals. format
// patches answers with the Bézier patches (a B-spline surface's decomposition) as the JSON POST /tessellate takes.
constexpr OptionSpec kTessellateOutput[] = {
    format_of(kMeshAndPatchFormats,
              "Encoding of the tessellated mesh, or patches: the Bézier patches (surfaces decomposed) as the JSON "
              "POST /tessellate takes"),
    kCompressionOption, kQuantizeOption, kNormalsOption};
constexpr OptionSpec kRepairOption{
    .name = "repair",
    .type = OptionType::Enum,
    .default_json = "\"auto\"",
    .description = "Repair a mesh that is not manifold first (auto), or refuse it (none)",
    .values = kRepairModes};

constexpr std::string_view kMeshInput[] = {"mesh"};
constexpr std::string_view kSubdivideInputs[] = {"mesh", "creases", "corners", "holes"};

constexpr std::string_view kTargetFacesAliases[] = {"max_faces"};  // its name before /simplify's was used
constexpr OptionSpec kSubdivide[] = {
    {.name = "scheme",
     .type = OptionType::Enum,
     .default_json = "\"catmull-clark\"",
     .description = "Subdivision scheme (loop needs triangles)",
     .values = kSchemes},
    {.name = "levels",
     .type = OptionType::Integer,
     .min = at_least(0),
     .max = at_most(8),
     .max_is_limit = true,  // Limits::max_levels
     .default_json = "1",
     .description = "Subdivision levels; each multiplies the face count by about 4"},
    {.name = "tolerance",
     .type = OptionType::Number,
     .min = above(0),
     .units = "model units",
     .description =
         "Instead of levels: triangles within this distance of the Catmull-Clark limit surface, with "
         "segments per edge chosen from its curvature; excludes levels and target_faces. With format patches: the "
         "largest error allowed of the approximated patches (a bound)"},
    {.name = "straddle",
     .type = OptionType::Number,
     .min = at_least(0),
     .max = below(1),
     .default_json = "0.45",
     .description = "With tolerance: vertices move off the limit surface along the normal, towards its convex side, "
                    "by straddle x tolerance where it curves one way (not on saddles, irregular vertices or "
                    "infinitely sharp features), so that the surface crosses the triangles; the distance stays "
                    "within the tolerance, with fewer triangles; 0: every vertex on the surface"},
    {.name = "target_faces",
     .type = OptionType::Integer,
     .min = at_least(1),
     .description = "Use the largest level (up to levels, if given) whose output has at most this many faces (level "
                    "0 when the input has more: X-Target-Met false)",
     .aliases = kTargetFacesAliases},
    {.name = "boundary",
     .type = OptionType::Enum,
     .description = "Boundary interpolation; unset: the mesh's own tag, else edge-only",
     .values = kBoundaries},
    {.name = "crease_method",
     .type = OptionType::Enum,
     .default_json = "\"uniform\"",
     .description = "How semi-sharp crease sharpness decays per level",
     .values = kCreaseMethods},
    {.name = "triangle_rule",
     .type = OptionType::Enum,
     .default_json = "\"catmark\"",
     .description = "Catmull-Clark weights on triangles",
     .values = kTriangleRules},
    {.name = "uv_interpolation",
     .type = OptionType::Enum,
     .default_json = "\"corners-plus1\"",
     .description = "Face-varying (UV) interpolation rule",
     .values = kUvInterpolations},
    {.name = "loop_weights",
     .type = OptionType::Enum,
     .default_json = "\"loop\"",
     .description = "Loop vertex weights",
     .values = kLoopWeights},
    {.name = "limit_surface",
     .type = OptionType::Bool,
     .default_json = "false",
     .description = "Project onto the limit surface; normals come from limit tangents"},
    {.name = "threads",
     .type = OptionType::Integer,
     .min = at_least(1),
     .max = at_most(2),
     .default_json = "1",
     .description = "2: a second thread for large levels and, with tolerance, for preparing and grading half of the "
                    "faces (the same mesh bit for bit as with 1)"},
};

constexpr OptionSpec kSimplify[] = {
    {.name = "target_faces",
     .type = OptionType::Integer,
     .min = at_least(0),
     .description = "Stop at this many faces (triangles)"},
    {.name = "ratio",
     .type = OptionType::Number,
     .min = above(0),
     .max = at_most(1),
     .description = "Stop at this fraction of the input's triangles"},
    {.name = "max_error",
     .type = OptionType::Number,
     .min = at_least(0),
     .units = "model units",
     .description = "Stop before the distance to the input exceeds this"},
    {.name = "lock_border",
     .type = OptionType::Bool,
     .default_json = "false",
     .description = "Boundary vertices keep their positions"},
    {.name = "restore_volume",
     .type = OptionType::Number,
     .min = at_least(0),
     .max = at_most(1),
     .default_json = "0",
     .description = "Fraction of the way each placement moves towards keeping the volume"},
    {.name = "threads",
     .type = OptionType::Integer,
     .min = at_least(1),
     .max = at_most(2),
     .default_json = "1",
     .description = "Threads for the first phase of a large mesh"},
    {.name = "report_error",
     .type = OptionType::Bool,
     .default_json = "false",
     .description = "Measure the Hausdorff and RMS distances to the input"},
    {.name = "locked_vertices",
     .type = OptionType::List,
     .min = at_least(0),
     .description = "Vertex indices that never move or disappear"},
    kRepairOption,
};

// /remesh's deprecated name for lock_border (the name /simplify, meshoptimizer and gltf-transform use)
constexpr std::string_view kLockBorderAliases[] = {"keep_boundary"};
constexpr OptionSpec kRemesh[] = {
    {.name = "edge_length",
     .type = OptionType::Number,
     .min = above(0),
     .units = "model units",
     .description = "Target edge length; unset: the input's mean edge length"},
    {.name = "iterations",
     .type = OptionType::Integer,
     .min = at_least(0),
     .max = at_most(100),
     .default_json = "10",
     .description = "Rounds of split, collapse, flip and smooth"},
    {.name = "feature_angle",
     .type = OptionType::Number,
     .min = at_least(0),
     .max = at_most(180),
     .default_json = "60",
     .units = "degrees",
     .description = "Edges whose dihedral angle exceeds this are kept as features (180: none)"},
    {.name = "lock_border",
     .type = OptionType::Bool,
     .default_json = "true",
     .description = "Boundary vertices stay on the input's border (moving an open mesh's border shrinks it)",
     .aliases = kLockBorderAliases},
    {.name = "smoothing",
     .type = OptionType::Enum,
     .default_json = "\"tangential\"",
     .description = "How vertices move after each round",
     .values = kSmoothings},
    kRepairOption,
};

constexpr OptionSpec kRepair[] = {
    {.name = "weld_tolerance",
     .type = OptionType::Number,
     .min = at_least(0),
     .default_json = "0",
     .units = "model units",
     .description = "Weld vertices closer than this (0: equal positions only)"},
    {.name = "orient",
     .type = OptionType::Bool,
     .default_json = "true",
     .description = "Orient every component consistently, outwards when closed"},
    {.name = "min_component_faces",
     .type = OptionType::Integer,
     .min = at_least(0),
     .default_json = "0",
     .description = "Drop components with fewer faces (0: keep all)"},
    {.name = "max_hole_edges",
     .type = OptionType::Integer,
     .min = at_least(0),
     .max = at_most(10'000),
     .default_json = "0",
     .description = "Fill holes with at most this many boundary edges (0: none)"},
};

// ---- Bezier patches: POST /tessellate (query or JSON) and GET /patches/{name} (query) -----------------------------
constexpr std::string_view kPatchesInput[] = {"patches", "surfaces"};
constexpr OptionSpec kTolerance{.name = "tolerance",
                                .type = OptionType::Number,
                                .min = above(0),
                                .units = "model units",
                                .description = "Largest distance between triangles and surface; excludes segments"};
constexpr OptionSpec kSegments{.name = "segments",
                               .type = OptionType::Integer,
                               .min = at_least(1),
                               .max = at_most(256),
                               .max_is_limit = true,  // Limits::max_patch_segments
                               .default_json = "8",
                               .description = "Segments along each direction of every patch; excludes tolerance"};
constexpr OptionSpec kTessellate[] = {kTolerance, kSegments};

// GET /patches/{name}: the same options, as query parameters only; format patches answers with the sample's control
// points (the JSON body POST /tessellate takes) instead of a mesh.
constexpr OptionSpec query_only(OptionSpec option) {
    option.transports = kQuery;
    return option;
}
constexpr OptionSpec kPatchSample[] = {query_only(kTolerance), query_only(kSegments)};
constexpr OptionSpec kPatchSampleOutput[] = {
    query_only(format_of(kMeshAndPatchFormats,
                         "Encoding of the tessellated sample as on POST /tessellate, or patches: its "
                         "control points (the JSON POST /tessellate takes)")),
    query_only(kCompressionOption), query_only(kQuantizeOption), query_only(kNormalsOption)};

// ---- POST /curves: a JSON body of curves and queries on them; its options are those of the output -----------------
// (line strips: no normals, and Draco is defined for triangles and points only)
constexpr std::string_view kCurveFormats[] = {"json", "glb", "gltf"};
constexpr std::string_view kCurveCompressions[] = {"none"};
constexpr OptionSpec kCurvesOutput[] = {
    {.name = "format",
     .type = OptionType::Enum,
     .default_json = "\"json\"",
     .description = "json: the answers to the queries; glb or gltf: the tessellation as line strips",
     .values = kCurveFormats,
     .transports = kJson,
     .json_object = "output"},
    {.name = "compression",
     .type = OptionType::Enum,
     .description = "Line strips are never compressed",
     .values = kCurveCompressions,
     .transports = kJson,
     .json_object = "output"},
};
constexpr std::string_view kCurvesInputs[] = {"points",       "weights",     "chain",      "svg",        "bspline",
                                              "evaluate",     "derivatives", "curvature",  "split",      "elevate",
                                              "bounding_box", "length",      "closest",    "tessellate", "continuity",
                                              "enforce_c1",   "to_bezier",   "insert_knot"};

// ---- POST /surfaces: one B-spline/NURBS surface and the queries on it (JSON only, no options) ------------------
constexpr std::string_view kSurfacesInputs[] = {"surface",     "evaluate", "derivatives", "closest",
                                                "insert_knot", "elevate",  "to_bezier",   "bounding_box"};

// ---- POST /implicit/mesh: a JSON body (the scene and its bounds, grid options, the mesh's output) ---------------
constexpr auto kImplicitModes = names_of(operations::kImplicitMeshModeNames);
constexpr OptionSpec json_only(OptionSpec option) {
    option.transports = kJson;
    return option;
}
constexpr std::string_view kImplicitMeshInputs[] = {"scene", "bounds"};
constexpr OptionSpec kImplicitMesh[] = {
    {.name = "resolution",
     .type = OptionType::Integer,
     .min = at_least(2),
     .max = at_most(65536),
     .default_json = "64",
     .description = "Cells along the longest side of the bounds; excludes cell_size",
     .transports = kJson},
    {.name = "cell_size",
     .type = OptionType::Number,
     .min = above(0),
     .units = "model units",
     .description = "Cell size instead of a resolution",
     .transports = kJson},
    {.name = "mode",
     .type = OptionType::Enum,
     .default_json = "\"uniform\"",
     .description = "Uniform grid, or adaptive octree with dual contouring",
     .values = kImplicitModes,
     .transports = kJson},
    {.name = "simplify_tolerance",
     .type = OptionType::Number,
     .min = at_least(0),
     .default_json = "0",
     .units = "model units",
     .description = "Adaptive mode only: simplify to this measured distance (0: none)",
     .transports = kJson},
    {.name = "crease_angle",
     .type = OptionType::Number,
     .min = at_least(0),
     .max = at_most(180),
     .default_json = "40",
     .units = "degrees",
     .description = "Vertices where faces meet at more than this get a normal per side (output.normals)",
     .transports = kJson},
};
constexpr OptionSpec kImplicitMeshOutput[] = {json_only(kFormatOption), json_only(kCompressionOption),
                                              json_only(kQuantizeOption), json_only(kNormalsOption)};

// ---- POST /implicit/query: a JSON body (the scene, points and rays, and how they are queried) --------------------
constexpr std::string_view kImplicitQueryInputs[] = {"scene", "points", "rays"};
constexpr OptionSpec kImplicitQuery[] = {
    {.name = "tolerance",
     .type = OptionType::Number,
     .min = at_least(0),
     .default_json = "1e-06",
     .description = "Points where |f| is at most this are on the surface",
     .transports = kJson},
    {.name = "max_distance",
     .type = OptionType::Number,
     .min = above(0),
     .default_json = "100",
     .units = "model units",
     .description = "Farthest distance along a ray that is searched",
     .transports = kJson},
    {.name = "max_steps",
     .type = OptionType::Integer,
     .min = at_least(1),
     .max = at_most(10'000),
     .max_is_limit = true,  // Limits::max_ray_steps
     .default_json = "1000",
     .description = "Field evaluations per ray (a ray that runs out is a miss)",
     .transports = kJson},
};

// ---- POST /pointcloud: a point file with query parameters, or a JSON body ---------------------------------------
// In a JSON body estimate_normals is true, false or {"k": n}: the operation reads that member itself and checks k
// against this table's row.
constexpr std::string_view kPointFormats[] = {"glb", "gltf", "ply", "json"};
constexpr std::string_view kPointCloudInputs[] = {"points", "normals", "colors", "sample", "estimate_normals"};
constexpr OptionSpec kPointCloud[] = {
    {.name = "estimate_normals",
     .type = OptionType::Bool,
     .default_json = "false",
     .description = "Estimate and orient normals from the k nearest neighbours",
     .transports = kQuery},
    {.name = "k",
     .type = OptionType::Integer,
     .min = at_least(3),
     .max = at_most(256),
     .default_json = "16",
     .description = "Neighbours for normal estimation (with estimate_normals)",
     .transports = kQuery},
};
constexpr OptionSpec kPointNormalsOption = [] {
    OptionSpec out = kNormalsOption;
    out.description = "false leaves normals out of the output";
    return out;
}();
constexpr OptionSpec kPointCloudOutput[] = {
    format_of(kPointFormats, "Encoding of the points: binary or text glTF, PLY or JSON"), kCompressionOption,
    kQuantizeOption, kPointNormalsOption};

// ---- POST /reconstruct: a point file with query parameters, or a JSON body (the cloud as /pointcloud takes it) ----
constexpr auto kPoissonBoundaries = names_of(operations::kPoissonBoundaryNames);
constexpr auto kNormalEstimations = names_of(operations::kNormalEstimationNames);
constexpr std::string_view kReconstructInputs[] = {"points", "normals", "colors"};
constexpr OptionSpec kReconstruct[] = {
    {.name = "depth",
     .type = OptionType::Integer,
     .min = at_least(2),
     .max = at_most(10),
     .max_is_limit = true,  // Limits::max_reconstruct_depth; the grid-cell and memory budgets also apply
     .default_json = "8",
     .description = "Finest octree level: 2^depth cells across the bounding cube; each level about 4x the time, "
                    "memory and triangles"},
    {.name = "point_weight",
     .type = OptionType::Number,
     .min = at_least(0),
     .default_json = "4",
     .description = "Screening weight: how strongly the surface is pulled through the points (0: unscreened Poisson)"},
    {.name = "samples_per_node",
     .type = OptionType::Number,
     .min = above(0),
     .default_json = "1.5",
     .description =
         "Samples a cell holds on a point's splatting level: larger smooths noisy clouds, 1 suits clean ones"},
    {.name = "boundary",
     .type = OptionType::Enum,
     .default_json = "\"neumann\"",
     .description = "Boundary condition on the bounding cube's faces",
     .values = kPoissonBoundaries},
    {.name = "scale",
     .type = OptionType::Number,
     .min = at_least(1),
     .max = at_most(100),
     .default_json = "1.1",
     .description = "Bounding cube side over the points' bounding box's largest side"},
    {.name = "fit_to_samples",
     .type = OptionType::Bool,
     .default_json = "true",
     .description = "Move each vertex onto the points' tangent planes after meshing (sharper creases, curved parts "
                    "closer where the cloud is dense; a noisy cloud's vertices move little); false: the indicator's "
                    "iso-surface as meshed"},
    {.name = "confidence",
     .type = OptionType::Bool,
     .default_json = "false",
     .description = "Weight each point by its normal's length (JSON normals are then kept as sent; zero drops it)"},
    {.name = "estimate_normals",
     .type = OptionType::Enum,
     .default_json = "\"auto\"",
     .description = "Estimate and orient normals from the k nearest neighbours: when the cloud has none (auto), "
                    "always, or never (a cloud without normals is refused)",
     .values = kNormalEstimations},
    {.name = "k",
     .type = OptionType::Integer,
     .min = at_least(3),
     .max = at_most(256),
     .default_json = "16",
     .description = "Neighbours for normal estimation (not with estimate_normals never)"},
    {.name = "trim",
     .type = OptionType::Number,
     .min = at_least(0),
     .default_json = "0",
     .description = "Cut away the surface where the sampling density, on the octree-depth scale, is below this (0: "
                    "keep all); useful 0.3 to 1 below X-Sample-Density"},
    {.name = "island_area",
     .type = OptionType::Number,
     .min = at_least(0),
     .max = at_most(1),
     .default_json = "0.001",
     .description = "With trim: pieces, and regions below the level, smaller than this fraction of the area are "
                    "removed, and kept, respectively"},
    {.name = "vertex_colors",
     .type = OptionType::Bool,
     .description = "Carry the points' colours to the vertices (glb, gltf, ply, obj, json); unset: when the cloud has "
                    "colours and the format holds them"},
    {.name = "threads",
     .type = OptionType::Integer,
     .min = at_least(1),
     .max = at_most(2),
     .default_json = "1",
     .description = "2: the octree, assembly, solver and meshing of large levels on two threads (the same mesh)"},
};

// ---- POST /mesh/query: a JSON body (the mesh, points and rays, what is wanted, how winding numbers are computed) ---
// "want" is an array of names, read by the operation itself.
constexpr std::string_view kMeshQueryEncodings[] = {"json", "float32", "float64"};
constexpr std::string_view kMeshQueryInputs[] = {"mesh", "points", "rays", "want"};
constexpr OptionSpec kMeshQuery[] = {
    {.name = "exact",
     .type = OptionType::Bool,
     .default_json = "false",
     .description = "Winding numbers by the exact sum over every triangle instead of the hierarchy",
     .transports = kJson,
     .json_object = "winding"},
    {.name = "accuracy",
     .type = OptionType::Number,
     .min = above(1),
     .default_json = "2",
     .description = "Hierarchy's beta: larger is more accurate and slower (about 5e-3 at 2, below 1e-3 at 3)",
     .transports = kJson,
     .json_object = "winding"},
    {.name = "encoding",
     .type = OptionType::Enum,
     .default_json = "\"json\"",
     .description = "How the answers' arrays are written: JSON numbers, or base64 of packed little-endian float32 or "
                    "float64 (booleans uint8, faces int32, -1 and NaN for none)",
     .values = kMeshQueryEncodings,
     .transports = kJson},
};

// ---- POST /implicit/grid: a JSON body (a mesh or a scene, the grid's bounds, voxel size and band) -----------------
// voxel_size has no default: the operation refuses a body without it.
constexpr std::string_view kImplicitGridInputs[] = {"mesh", "scene", "bounds"};
constexpr OptionSpec kImplicitGrid[] = {
    {.name = "voxel_size",
     .type = OptionType::Number,
     .min = above(0),
     .units = "model units",
     .description = "Grid spacing (required); the node count is checked against the level-set sample limit",
     .transports = kJson},
    {.name = "band",
     .type = OptionType::Integer,
     .min = at_least(1),
     .max = at_most(64),  // implicit::kMaxDistanceBand
     .default_json = "3",
     .units = "voxels",
     .description = "Nodes within this many voxels of the surface get exact distances, the others +-band * voxel_size",
     .transports = kJson},
};

// ---- POST /limit/evaluate: a JSON body (the mesh, its tags, (face, u, v) points), the surface's /subdivide options -
// "points" is read by the operation itself; the subdivide rows are /subdivide's own, JSON only.
constexpr OptionSpec json_row_of(std::span<const OptionSpec> table, std::string_view name) {
    for (const OptionSpec& option : table)
        if (option.name == name) {
            OptionSpec out = option;
            out.transports = kJson;
            return out;
        }
    return OptionSpec{};
}
constexpr std::string_view kLimitEvaluateInputs[] = {"mesh", "points", "creases", "corners", "holes"};
constexpr OptionSpec kLimitEvaluate[] = {
    json_row_of(kSubdivide, "scheme"),
    json_row_of(kSubdivide, "boundary"),
    json_row_of(kSubdivide, "crease_method"),
    json_row_of(kSubdivide, "triangle_rule"),
    json_row_of(kSubdivide, "uv_interpolation"),
    {.name = "derivatives",
     .type = OptionType::Integer,
     .min = at_least(1),
     .max = at_most(2),
     .default_json = "1",
     .description = "Highest derivative order answered: 1 (du, dv, normal) or 2 (also duu, duv, dvv)",
     .transports = kJson},
    {.name = "encoding",
     .type = OptionType::Enum,
     .default_json = "\"json\"",
     .description = "How the answers are written: one JSON object per point, or base64 of packed little-endian "
                    "float32 or float64 arrays per member (exact as uint8)",
     .values = kMeshQueryEncodings,
     .transports = kJson},
};

constexpr OperationOptions kOperations[] = {
    {"subdivide", "/subdivide", "post", kSubdivide, kSubdivideOutput, kSubdivideInputs},
    {"simplify", "/simplify", "post", kSimplify, kMeshOutput, kMeshInput},
    {"remesh", "/remesh", "post", kRemesh, kMeshOutput, kMeshInput},
    {"repair", "/repair", "post", kRepair, kMeshOutput, kMeshInput},
    {"tessellate", "/tessellate", "post", kTessellate, kTessellateOutput, kPatchesInput},
    {"patches", "/patches/{name}", "get", kPatchSample, kPatchSampleOutput, {}},
    {"pointcloud", "/pointcloud", "post", kPointCloud, kPointCloudOutput, kPointCloudInputs},
    {"curves", "/curves", "post", {}, kCurvesOutput, kCurvesInputs},
    {"implicit_mesh", "/implicit/mesh", "post", kImplicitMesh, kImplicitMeshOutput, kImplicitMeshInputs},
    {"implicit_query", "/implicit/query", "post", kImplicitQuery, {}, kImplicitQueryInputs},
    {"mesh_query", "/mesh/query", "post", kMeshQuery, {}, kMeshQueryInputs},
    {"surfaces", "/surfaces", "post", {}, {}, kSurfacesInputs},
    {"implicit_grid", "/implicit/grid", "post", kImplicitGrid, {}, kImplicitGridInputs},
    {"limit_evaluate", "/limit/evaluate", "post", kLimitEvaluate, {}, kLimitEvaluateInputs},
    {"reconstruct", "/reconstruct", "post", kReconstruct, kMeshOutput, kReconstructInputs},
};

}  // namespace

std::span<const OperationOptions> operations() { return kOperations; }

const OperationOptions* operation_options(std::string_view operation) {
    for (const auto& op : kOperations)
        if (op.operation == operation) return &op;
    return nullptr;
}

std::vector<const OptionSpec*> all_options(const OperationOptions& operation) {
    std::vector<const OptionSpec*> out;
    for (const auto& option : operation.options) out.push_back(&option);
    for (const auto& option : operation.output) out.push_back(&option);
    return out;
}

const OptionSpec* find_option(const OperationOptions& operation, std::string_view name) {
    for (const OptionSpec* option_ptr : all_options(operation)) {
        const OptionSpec& option = *option_ptr;
        if (option.name == name) return &option;
        if (std::find(option.aliases.begin(), option.aliases.end(), name) != option.aliases.end()) return &option;
    }
    return nullptr;
}

}  // namespace surfaced::api::options
