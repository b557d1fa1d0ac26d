// Plain request/response structs of the API (oatpp's dto/): what a request asks for once decoded, whether it
// came as JSON or as a raw mesh upload with query parameters. Also the wire names of every enum, in one table each,
// so JSON fields, query parameters, the CLI and error messages agree.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/remesh/remesh.h"
#include "geometry/repair/repair.h"
#include "geometry/subdivision/subdivide.h"

namespace surfaced::api {

enum class OutputFormat { Glb, Gltf, Obj, Ply, Json, Stl, Off };

//! How the result is encoded. Unset optionals mean "the default"; they are optional so that an option that does
//! not apply to the chosen format (compression with OBJ) can be rejected instead of silently ignored.
struct OutputOptions {
    OutputFormat format = OutputFormat::Glb;
    std::optional<bool> draco;                      //!< glb only; default true ("compression": "draco"|"none")
    std::optional<std::int64_t> quantize_position;  //!< glb with Draco only; 1..24, default 14
    //! Vertex normals (computed when the mesh has none) in the formats that hold them (glb, gltf, obj, ply, json);
    //! default true. STL has facet normals only and OFF none: there the default does not apply and true is an error.
    std::optional<bool> normals;
    bool format_given = false;  //!< the request named `format` (else its Accept header may choose one)
};

struct SubdivideParams {
    SubdivisionScheme scheme = SubdivisionScheme::CatmullClark;
    std::int64_t levels = 1;  //!< as sent; range-checked by the operation against Limits::max_levels
    //! Unset: the mesh's own `t interpolateboundary` tag if it has one, else edge-only. Set: overrides the tag.
    std::optional<BoundaryInterpolation> boundary;
    CreaseMethod crease_method = CreaseMethod::Uniform;
    TriangleRule triangle_rule = TriangleRule::Catmark;
    bool limit_surface = false;  //!< project to the limit surface; normals then come from limit tangents
    UvInterpolation uv_interpolation = UvInterpolation::CornersPlus1;
    LoopWeights loop_weights = LoopWeights::Loop;
    //! Choose the largest level (up to `levels` when given, else the server's maximum) whose output stays within
    //! this many faces.
    std::optional<std::int64_t> target_faces;
    bool levels_given = false;  //!< whether "levels" was sent (it bounds the level chosen for target_faces)
    //! Instead of levels: triangles within this distance of the Catmull-Clark limit surface (adaptive_tessellation.h)
    std::optional<double> tolerance;
    //! With tolerance: LimitTessellationOptions::straddle (unset: the library's default, kDefaultStraddle)
    std::optional<double> straddle;
    OutputOptions output;
    //! format "patches": the limit surface as Bézier patches (`levels` given: the isolation level) instead of a mesh
    bool patches = false;
    std::int64_t threads = 1;  //!< 1 or 2 (SubdivisionOptions::threads, LimitTessellationOptions::threads)
};

struct SubdivideStats {
    std::size_t input_vertices = 0, input_faces = 0;
    std::size_t output_vertices = 0, output_faces = 0;
    SubdivisionScheme scheme = SubdivisionScheme::CatmullClark;
    int levels = 0;
    std::optional<std::int64_t> target_faces;  //!< as requested; with it, whether the output is within it
    bool target_met = true;
    double elapsed_ms = 0;  //!< decode + budget checks + subdivision (encoding the response is not included)
};

//! POST /simplify. At least one of target_faces, ratio, max_error (the operation checks it and the ranges).
//! What an operation that needs a manifold mesh does with one that is not: repair it first (auto, the default) or
//! refuse it (none: 422 naming the edge or face).
enum class RepairMode { Auto, None };

struct SimplifyParams {
    std::optional<std::int64_t> target_faces;
    std::optional<double> ratio;      //!< (0, 1]
    std::optional<double> max_error;  //!< absolute distance, >= 0
    bool lock_border = false;
    double restore_volume = 0;                  //!< [0, 1]: volume restoration (SimplifyOptions::restore_volume)
    std::int64_t threads = 1;                   //!< 1 or 2 (SimplifyOptions::threads)
    bool report_error = false;                  //!< measure Hausdorff/RMS to the input and return them
    std::vector<std::int64_t> locked_vertices;  //!< vertices that never move or disappear (checked against the mesh)
    RepairMode repair = RepairMode::Auto;
    OutputOptions output;
};

struct SimplifyStats {
    std::size_t input_vertices = 0, input_faces = 0;
    std::size_t output_vertices = 0, output_faces = 0;
    bool triangulated = false;
    double achieved_error = 0, relative_error = 0;  //!< see SimplifyResult
    std::optional<double> hausdorff, rms;           //!< when report_error
    std::optional<RepairReport> repairs;            //!< repair "auto": what was repaired before simplifying
    //! The face count worked toward: target_faces, floor(ratio x the triangles simplified), the smaller when both
    //! were given; unset with max_error alone.
    std::optional<std::size_t> target_faces;
    std::size_t achieved_faces = 0;  //!< the output's faces (triangles)
    //! achieved_faces <= target_faces <= the triangles simplified (simplification never adds faces); true with
    //! max_error alone (the output is always within it).
    bool target_met = true;
    double elapsed_ms = 0;
};

template <class E>
struct EnumName {
    std::string_view name;
    E value;
};

inline constexpr EnumName<RepairMode> kRepairModeNames[] = {
    {"auto", RepairMode::Auto},
    {"none", RepairMode::None},
};

//! POST /remesh: how vertices are moved after each round of splits, collapses and flips.
inline constexpr EnumName<RemeshSmoothing> kRemeshSmoothingNames[] = {
    {"tangential", RemeshSmoothing::Tangential},
    {"laplacian", RemeshSmoothing::Laplacian},
    {"none", RemeshSmoothing::None},
};

inline constexpr EnumName<SubdivisionScheme> kSchemeNames[] = {
    {"catmull-clark", SubdivisionScheme::CatmullClark},
    {"loop", SubdivisionScheme::Loop},
};
//! OpenSubdiv's VTX_BOUNDARY_* names, lower-case and hyphenated.
inline constexpr EnumName<BoundaryInterpolation> kBoundaryNames[] = {
    {"edge-only", BoundaryInterpolation::EdgeOnly},
    {"edge-and-corner", BoundaryInterpolation::EdgeAndCorner},
    {"none", BoundaryInterpolation::None},
};
//! OpenSubdiv's CREASE_UNIFORM / CREASE_CHAIKIN.
inline constexpr EnumName<CreaseMethod> kCreaseMethodNames[] = {
    {"uniform", CreaseMethod::Uniform},
    {"chaikin", CreaseMethod::Chaikin},
};
//! OpenSubdiv's TRI_SUB_CATMARK / TRI_SUB_SMOOTH.
inline constexpr EnumName<TriangleRule> kTriangleRuleNames[] = {
    {"catmark", TriangleRule::Catmark},
    {"smooth", TriangleRule::Smooth},
};
//! "loop": Loop's original weights, as OpenSubdiv; "warren": 3/(8n), not OpenSubdiv's.
inline constexpr EnumName<LoopWeights> kLoopWeightNames[] = {
    {"loop", LoopWeights::Loop},
    {"warren", LoopWeights::Warren},
};
//! OpenSubdiv's FVAR_LINEAR_* rules, lower-case and hyphenated.
inline constexpr EnumName<UvInterpolation> kUvInterpolationNames[] = {
    {"none", UvInterpolation::None},
    {"corners-only", UvInterpolation::CornersOnly},
    {"corners-plus1", UvInterpolation::CornersPlus1},
    {"corners-plus2", UvInterpolation::CornersPlus2},
    {"boundaries", UvInterpolation::Boundaries},
    {"all", UvInterpolation::All},
};
inline constexpr EnumName<OutputFormat> kOutputFormatNames[] = {
    {"glb", OutputFormat::Glb},   {"gltf", OutputFormat::Gltf}, {"obj", OutputFormat::Obj}, {"ply", OutputFormat::Ply},
    {"json", OutputFormat::Json}, {"stl", OutputFormat::Stl},   {"off", OutputFormat::Off},
};
//! "compression": value true means Draco.
inline constexpr EnumName<bool> kCompressionNames[] = {
    {"draco", true},
    {"none", false},
};

//! The media type we send for each mesh file format, and the one we always accept for it (format_from_media_type
//! in geometry/io may accept more aliases). OFF and PLY have no registered media type; these are the common ones.
inline constexpr EnumName<MeshFormat> kMeshMediaTypes[] = {
    {"model/obj", MeshFormat::Obj}, {"model/off", MeshFormat::Off},         {"application/ply", MeshFormat::Ply},
    {"model/stl", MeshFormat::Stl}, {"model/gltf-binary", MeshFormat::Glb}, {"model/gltf+json", MeshFormat::Gltf},
};

template <class E, std::size_t N>
std::optional<E> enum_from_name(const EnumName<E> (&table)[N], std::string_view name) {
    for (const auto& entry : table)
        if (entry.name == name) return entry.value;
    return std::nullopt;
}

template <class E, std::size_t N>
std::string_view enum_name(const EnumName<E> (&table)[N], E value) {
    for (const auto& entry : table)
        if (entry.value == value) return entry.name;
    return "?";
}

//! "\"catmull-clark\", \"loop\"": the allowed values, for error messages.
template <class E, std::size_t N>
std::string enum_names(const EnumName<E> (&table)[N]) {
    std::string out;
    for (const auto& entry : table) {
        if (!out.empty()) out += ", ";
        out += '"';
        out += entry.name;
        out += '"';
    }
    return out;
}

}  // namespace surfaced::api
