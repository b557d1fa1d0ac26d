// What every operation that takes a mesh (or patches) shares: the two request forms (a JSON body, or a raw file body
// with options as query parameters), media types, query-parameter parsing with named errors, error field paths,
// timing, and the never-throw guard. One copy, so every endpoint words its errors the same way.
#pragma once

#include <chrono>
#include <initializer_list>
#include <exception>
#include <map>
#include <new>
#include <optional>
#include <string>
#include <string_view>

#include "api/dto.h"
#include "api/errors.h"
#include "api/operation.h"
#include "geometry/core/result.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::api::operations {

using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b);
//! "%.3f"
std::string format_ms(double ms);
//! Shortest text that reads back as the same double.
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

//! Query parameters: each error names the parameter and what was expected.
ApiResult<std::int64_t> parse_integer_parameter(const std::string& name, const std::string& text);
ApiResult<double> parse_number_parameter(const std::string& name, const std::string& text);
ApiResult<bool> parse_bool_parameter(const std::string& name, const std::string& text);
template <class E, std::size_t N>
ApiResult<E> parse_enum_parameter(const std::string& name, const std::string& text, const EnumName<E> (&table)[N]) {
    if (auto value = enum_from_name(table, text)) return *value;
    return make_problem(Problem::InvalidField,
                        "query parameter " + name + ": unknown value \"" + text + "\" (allowed: " + enum_names(table) + ")",
                        name);
}

// ---- the two request forms ----------------------------------------------------------------------------------------

//! Body size against the budget, then a Content-Type (normalised into `media_type`): both before anything is parsed.
std::optional<ApiError> check_body(const ApiRequest& request, const Limits& limits, std::string& media_type);
//! Options of a JSON request go in its body: query parameters with it are an error naming the first one.
std::optional<ApiError> reject_query_with_json(const ApiRequest& request);
//! Parameters must be known and given once; errors name them (and list the allowed ones).
std::optional<ApiError> check_query_names(const std::multimap<std::string, std::string>& query,
                                          std::initializer_list<std::string_view> allowed);
//! A raw mesh upload: format from the media type (sniffed for application/octet-stream; 415 when unknown), read with
//! the input budgets as reader limits (errors carry the file line or byte offset).
ApiResult<PolygonMesh> read_uploaded_mesh(const ApiRequest& request, const std::string& media_type, const Limits& limits);
//! The input budgets (vertices, faces) for a mesh from any source.
std::optional<ApiError> check_input_budget(const PolygonMesh& mesh, const Limits& limits);

//! "output" options that do not fit the format (compression with OBJ, ...), named by their JSON path (`output.x`) or
//! query name.
std::optional<ApiError> check_output_options(const OutputOptions& out, Source source);
//! The mesh in the requested format (GLB/glTF with Draco unless compression "none", OBJ, PLY); JSON is the
//! operation's own (`encode_json`). Normals are written when asked (computed if the mesh has none).
ApiResult<std::string> encode_mesh_file(PolygonMesh& mesh, const OutputOptions& out, Source source);
template <class EncodeJson>
ApiResult<std::string> encode_mesh_output(PolygonMesh& mesh, const OutputOptions& out, Source source,
                                          EncodeJson&& encode_json) {
    if (out.format == OutputFormat::Json) return encode_json(mesh);
    return encode_mesh_file(mesh, out, source);
}
//! The output options as query parameters (format, compression, quantize_position, normals): true when `name` was one
//! of them (and is now in `out`), false when it is not an output option.
ApiResult<bool> parse_output_parameter(const std::string& name, const std::string& text, OutputOptions& out);

//! Runs an operation body; anything escaping it (a bug, or memory exhaustion) becomes a 500 envelope, so that the
//! Operation contract "never throws" holds.
template <class F>
ApiResponse guarded(F&& body) noexcept {
    try {
        return body();
    } catch (const std::bad_alloc&) {
        return error_response(make_problem(Problem::Internal, "out of memory while processing the request"));
    } catch (const std::exception& e) {
        return error_response(make_problem(Problem::Internal, std::string("internal error: ") + e.what()));
    } catch (...) {
        return error_response(make_problem(Problem::Internal, "internal error"));
    }
}

}  // namespace surfaced::api::operations
