// What every operation that takes a mesh (or patches) shares: the two request forms (a JSON body, or a raw file body
// with options as query parameters, which a multipart/form-data body also stands for), media types, the output format
// from `format` or the Accept header, query-parameter parsing with named errors, error field paths,
// timing, and the never-throw guard. One copy, so every endpoint words its errors the same way.
#pragma once

#include <chrono>
#include <exception>
#include <map>
#include <new>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "api/dto.h"
#include "api/errors.h"
#include "api/multipart.h"
#include "api/operation.h"
#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::api::operations {

using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b);
//! Milliseconds rounded to the microsecond, printed as format_double prints ("1.25", "12").
std::string format_ms(double ms);
//! Shortest text that reads back as the same double, integral values without a fraction, -0 as "0"
//! (geometry/io/number_text.h: every text output prints numbers this way).
std::string format_double(double value);

//! "Application/JSON; charset=utf-8" -> "application/json".
std::string media_type_of(std::string_view content_type);
//! "application/json, model/obj, ... application/octet-stream (...)": for 415 messages.
std::string accepted_mesh_media_types();
//! Mesh file format of a raw body: by media type, or sniffed from the bytes for application/octet-stream.
std::optional<MeshFormat> mesh_format_for(const std::string& media_type, std::string_view body);
//! The media type we answer with for each output format.
std::string_view output_media_type(OutputFormat format);

//! Where a request's data came from: a JSON body has field paths, a file has lines and offsets.
enum class Source { Json, File };
//! The API error for a GeoError, with the JSON field path of the element it names (when the request was JSON).
ApiError geometry_error(const GeoError& error, Source source);
//! The same, and for an uploaded text file the line of the face the error names (ReadReport::face_lines, kept by
//! the reader), as `line` and at the start of the detail: for errors found after reading (a face Loop subdivision
//! cannot take, a non-manifold edge). Binary files have no lines: the detail's face index names the element.
ApiError geometry_error(const GeoError& error, Source source, const ReadReport& read);

//! Query parameters: each error names the parameter and what was expected (the option readers of api/options use
//! them).
ApiResult<std::int64_t> parse_integer_parameter(const std::string& name, const std::string& text);
ApiResult<double> parse_number_parameter(const std::string& name, const std::string& text);
ApiResult<bool> parse_bool_parameter(const std::string& name, const std::string& text);

// ---- the two request forms ----------------------------------------------------------------------------------------

//! Body size against the budget, a body at all (400 empty_body), then a Content-Type (normalised into `media_type`):
//! all before anything is parsed. `accepted` lists the endpoint's media types, for those two errors.
std::optional<ApiError> check_body(const ApiRequest& request, const Limits& limits, std::string& media_type,
                                   std::string_view accepted);
// ---- multipart/form-data: the raw-file form sent as an HTML form or curl -F ---------------------------------------

//! Whether an endpoint reads files of `media_type` (normalised): how a file part's declared type is judged.
using ReadsMediaType = bool (*)(std::string_view media_type);
//! The media type a file name's extension stands for (.obj model/obj, .ply application/ply, .json application/json,
//! .bez application/x-geomview-bez, .xyz text/x-xyz, ...); empty when the extension says nothing.
std::string media_type_for_filename(std::string_view filename);
//! Whether a mesh endpoint reads `media_type`: application/json, a mesh file type, or application/octet-stream.
bool reads_mesh_media_type(std::string_view media_type);
//! ", multipart/form-data (...)": the tail every upload endpoint's list of accepted media types ends with.
std::string_view multipart_media_type_note();

//! The media type of a multipart file part: its Content-Type when `reads` takes it (application/octet-stream and
//! text/plain only when the file name's extension names no type `reads` takes), else its extension's type, else
//! application/octet-stream.
std::string file_part_media_type(const MultipartPart& part, ReadsMediaType reads);

//! The request an upload endpoint reads: the request itself, or for a multipart/form-data body the raw-file request
//! it stands for (held in `form`, whose body is a view into the original body).
struct Upload {
    const ApiRequest* request = nullptr;
    std::string media_type;  //!< of `request`'s body, normalised
    ApiRequest form;

    Upload() = default;
    Upload(const Upload&) = delete;
    Upload& operator=(const Upload&) = delete;
};
//! check_body, then for a multipart/form-data body: its parts (400 malformed_multipart naming what is wrong), exactly
//! one file part (a part with a filename, or the part named "file"; 400 malformed_multipart for none or two, 400
//! empty_body when it is empty) as the body, and the other parts as query parameters, read by the same option
//! readers (an option given both as a query parameter and as a form field is 400 invalid_field naming it). The file
//! part's media type: its Content-Type when `reads` takes it (application/octet-stream and text/plain only when the
//! file name's extension names no type `reads` takes), else its extension's type, else application/octet-stream.
std::optional<ApiError> check_upload(const ApiRequest& request, const Limits& limits, std::string_view accepted,
                                     ReadsMediaType reads, Upload& out);

//! An option error about a field of a multipart form, worded as one ("form field levels ...", not "query parameter
//! levels ..."): the option readers word errors for query parameters, which is what form fields are read as. Other
//! errors unchanged.
ApiError worded_for_form(const ApiRequest& request, ApiError error);

// ---- the output format: `format`, else the Accept header ------------------------------------------------------------

//! When the request named no format (`out.format_given`) and sent an Accept header: the format of the endpoint at
//! `request.path` (the values of its option table's "format") whose media type Accept prefers (a tie: the default);
//! 406 not_acceptable listing the media types offered when Accept takes none of them. Endpoints without a "format"
//! option keep their one media type.
std::optional<ApiError> negotiate_output_format(const ApiRequest& request, OutputOptions& out);

// ---- JSON bodies --------------------------------------------------------------------------------------------------

//! Options of a JSON request go in its body: query parameters with it are an error naming the first one.
std::optional<ApiError> reject_query_with_json(const ApiRequest& request);
//! The intake of an endpoint that takes only a JSON body (`operation` names it in the message, e.g.
//! "POST /curves"): body size, Content-Type application/json, no query parameters.
std::optional<ApiError> check_json_only_body(const ApiRequest& request, const Limits& limits,
                                             std::string_view operation);
//! What the input mesh must satisfy: `validate()` (Strict), or `validate_for_subdivision()` (faces may repeat a vertex,
//! as OpenSubdiv allows: /subdivide; and the operations that repair their input, which drops such faces).
enum class MeshRules { Strict, Subdivision };
//! A raw mesh upload: format from the media type (sniffed for application/octet-stream; 415 when unknown), read with
//! the input budgets as reader limits (errors carry the file line or byte offset).
ApiResult<PolygonMesh> read_uploaded_mesh(const ApiRequest& request, const std::string& media_type,
                                          const Limits& limits, MeshRules rules = MeshRules::Strict,
                                          ReadReport* report = nullptr);
//! The input budgets (vertices, faces) for a mesh from any source.
std::optional<ApiError> check_input_budget(const PolygonMesh& mesh, const Limits& limits);

//! A mesh operation's request, decoded from either form, with the mesh within the input budget and valid.
template <class Params>
struct MeshRequest {
    Source source = Source::File;
    Params params;
    PolygonMesh mesh;
    Clock::time_point decoded;  //!< when decoding ended (before the budget and validity checks), for Server-Timing
    ReadReport read;  //!< what the file reader passed over (glTF point and line primitives); each face's line (text)
};

//! 415 for an upload whose mesh format is unknown (checked before the query, so that a wrong file type is named
//! first); nullopt when the format is known.
std::optional<ApiError> refuse_unknown_mesh_format(const ApiRequest& request, const std::string& media_type,
                                                   const Limits& limits);
//! The input budgets and the mesh's validity (field paths when the request was JSON).
std::optional<ApiError> check_mesh_input(const PolygonMesh& mesh, const Limits& limits, Source source,
                                         MeshRules rules = MeshRules::Strict);
//! Triangulation turns an n-gon into n - 2 triangles: for operations whose work is proportional to those.
std::optional<ApiError> check_triangulated_budget(const PolygonMesh& mesh, const Limits& limits);
//! Whether `format` stores coordinates as float32 (glTF and GLB, Draco or not, and STL; OBJ, PLY, OFF and JSON keep
//! doubles).
bool float32_format(OutputFormat format);
//! Whether `format` can hold vertex normals (all but STL, which has facet normals only, and OFF).
bool normals_format(OutputFormat format);
//! Whether the output carries vertex normals: a format that holds them, and `normals` true or unset (the default).
bool output_normals(const OutputOptions& out);
//! The mesh's normals as the output wants them: computed when wanted and missing (or not one per vertex), dropped
//! when not wanted.
void prepare_normals(PolygonMesh& mesh, const OutputOptions& out);
//! 422 coordinate_out_of_range naming the first of `positions` with a coordinate beyond float32 (|c| > FLT_MAX, which
//! a float32 accessor, min/max or Draco cannot hold): its index, axis and value; `element` names what the positions
//! are ("output vertex", "input vertex", "point") and `field`, when given, the JSON path of the array.
std::optional<ApiError> check_float32_range(const std::vector<Vec3>& positions, OutputFormat format,
                                            std::string_view element, std::optional<std::string_view> field = {});
//! 503 `cancelled` when the request's deadline passed while computing (encoding cannot be stopped, so check first).
std::optional<ApiError> check_deadline_before_encoding(const Cancel& cancel);

//! The two request forms of a mesh operation, each checked in the same order:
//! 1. body size and media type, before anything is parsed (a multipart/form-data body: its file part and fields);
//! 2. a JSON body: no query parameters, `decode_json(body, limits)` (an ApiResult of something with `params` and
//!    `mesh`), `check_params(params, Source::Json)`; or an uploaded file: a known format (415), then
//!    `params_from_query(query)` and `check_params(params, Source::File)`, both before the file is read; in both, a
//!    format not named comes from the Accept header (before check_params);
//! 3. the input budget and the mesh's validity.
//! `rules` are the reader's and validity rules; for a Params with a `repair` member (operations that repair their input
//! and so pass the lenient rules), repair "none" means the strict ones.
//! The operation states only what differs: its options, their decoders and their checks.
template <class Params, class DecodeJson, class ParamsFromQuery, class CheckParams>
ApiResult<MeshRequest<Params>> decode_mesh_request(const ApiRequest& sent, const Limits& limits,
                                                   DecodeJson&& decode_json, ParamsFromQuery&& params_from_query,
                                                   CheckParams&& check_params, MeshRules rules = MeshRules::Strict) {
    Upload upload;
    if (auto error = check_upload(sent, limits, accepted_mesh_media_types(), reads_mesh_media_type, upload))
        return std::move(*error);
    const ApiRequest& request = *upload.request;
    const std::string& media_type = upload.media_type;
    MeshRequest<Params> out;
    // A format the request did not name comes from its Accept header (before the checks of the output options).
    const auto negotiate = [&]() -> std::optional<ApiError> {
        if constexpr (requires { out.params.output.format; })
            return negotiate_output_format(request, out.params.output);
        return std::nullopt;
    };
    // An operation that repairs its input reads it leniently (`rules`), unless the request says repair "none": then
    // the strict rules, with their errors at the file's line.
    const auto effective_rules = [&] {
        if constexpr (requires { out.params.repair; })
            if (out.params.repair == RepairMode::None) return MeshRules::Strict;
        return rules;
    };
    if (media_type == "application/json") {
        out.source = Source::Json;
        if (auto error = reject_query_with_json(request)) return std::move(*error);
        auto decoded = decode_json(request.body, limits);
        if (!decoded) return std::move(decoded.error());
        out.params = std::move(decoded->params);
        if (auto error = negotiate()) return std::move(*error);
        if (auto error = check_params(out.params, out.source)) return std::move(*error);
        out.mesh = std::move(decoded->mesh);
    } else {
        if (auto error = refuse_unknown_mesh_format(request, media_type, limits)) return std::move(*error);
        auto query_params = params_from_query(request.query);
        if (!query_params) return worded_for_form(request, std::move(query_params.error()));
        out.params = std::move(query_params.value());
        if (auto error = negotiate()) return std::move(*error);
        if (auto error = check_params(out.params, out.source)) return worded_for_form(request, std::move(*error));
        auto read = read_uploaded_mesh(request, media_type, limits, effective_rules(), &out.read);
        if (!read) return std::move(read.error());
        out.mesh = std::move(read.value());
    }
    out.decoded = Clock::now();
    if (auto error = check_mesh_input(out.mesh, limits, out.source, effective_rules())) return std::move(*error);
    // An input vertex a float32 output cannot hold is named where the client wrote it (the output is checked again
    // when encoded, for vertices the operation moved there).
    if constexpr (requires { out.params.output.format; })
        if (auto error = check_float32_range(
                out.mesh.positions, out.params.output.format, "input vertex",
                out.source == Source::Json ? std::optional<std::string_view>("mesh.positions") : std::nullopt))
            return std::move(*error);
    return out;
}

// ---- the response -------------------------------------------------------------------------------------------------

using Headers = std::vector<std::pair<std::string, std::string>>;

//! The stages of a request for Server-Timing: each runs from the end of the previous one (the first from `start`).
struct Timing {
    Clock::time_point start;
    std::vector<std::pair<std::string_view, Clock::time_point>> stages;  //!< name, end
};
//! X-Input-Vertices, X-Input-Faces, X-Output-Vertices, X-Output-Faces.
Headers mesh_count_headers(std::size_t input_vertices, std::size_t input_faces, std::size_t output_vertices,
                           std::size_t output_faces);
//! X-Skipped-Primitives when the reader passed over any (glTF point and line primitives have no surface).
void append_read_headers(Headers& headers, const ReadReport& read);
//! Appends X-Elapsed-Ms (start to the end of the last stage) and Server-Timing ("decode;dur=1.234, ...,
//! total;dur=...").
void append_timing_headers(Headers& headers, const Timing& timing);

//! "output" options that do not fit the format (compression with OBJ, ...), named by their JSON path (`output.x`) or
//! query name.
std::optional<ApiError> check_output_options(const OutputOptions& out, Source source);
//! Per-vertex colours for the formats that hold them: glTF COLOR_0, PLY uchar red green blue (alpha), OBJ
//! `v x y z r g b`. Empty: none.
struct VertexColors {
    std::span<const Color> colors{};
    bool alpha = false;
};
//! The mesh in the requested format (GLB/glTF with Draco unless compression "none", OBJ, PLY, binary STL, OFF); JSON
//! is the operation's own (`encode_json`). Vertex normals are written unless `normals` is false (computed if the mesh
//! has none) in the formats that hold them; UVs go into glTF and OBJ when the mesh has them; `colors` (one per
//! vertex) into glTF, PLY and OBJ.
ApiResult<std::string> encode_mesh_file(PolygonMesh& mesh, const OutputOptions& out, Source source,
                                        VertexColors colors = {});
//! encode_mesh_file (with `colors`), or for format json `encode_json(mesh)` with the mesh's normals prepared (prepare_normals), so
//! that a JSON mesh carries "normals" exactly when the other formats would.
template <class EncodeJson>
ApiResult<std::string> encode_mesh_output(PolygonMesh& mesh, const OutputOptions& out, Source source,
                                          EncodeJson&& encode_json, VertexColors colors = {}) {
    if (out.format == OutputFormat::Json) {
        prepare_normals(mesh, out);
        return encode_json(mesh);
    }
    return encode_mesh_file(mesh, out, source, colors);
}
//! A mesh operation's response: the mesh in the requested format (JSON by `encode_json`; `colors` as in
//! encode_mesh_file), its media type, and the headers: `headers` (counts, the operation's own), then the timing ones
//! with a last stage "encode" ending now.
template <class EncodeJson>
ApiResponse mesh_response(PolygonMesh& mesh, const OutputOptions& out, Source source, EncodeJson&& encode_json,
                          Headers headers, Timing timing, VertexColors colors = {}) {
    ApiResponse response;
    response.content_type = std::string(output_media_type(out.format));
    auto encoded = encode_mesh_output(mesh, out, source, std::forward<EncodeJson>(encode_json), colors);
    if (!encoded) return error_response(std::move(encoded.error()));
    response.body = std::move(encoded.value());
    timing.stages.emplace_back("encode", Clock::now());
    append_timing_headers(headers, timing);
    response.headers = std::move(headers);
    return response;
}
//! Runs an operation body; anything escaping it (a bug, or memory exhaustion) becomes a 500 envelope, so that the
//! Operation contract "never throws" holds.
template <class F>
ApiResponse guarded(F&& body) noexcept {
    try {
        return body();
    } catch (const std::bad_alloc&) {
        return error_response(make_problem(Problem::Internal, "out of memory while processing the request"));
    } catch (...) {
        // A library's exception text says nothing useful to a client (and may show internals).
        return error_response(make_problem(Problem::Internal, "internal error"));
    }
}

}  // namespace surfaced::api::operations
