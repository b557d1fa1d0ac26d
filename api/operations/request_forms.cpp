#include "api/operations/request_forms.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "api/accept.h"
#include "api/multipart.h"
#include "api/options/option_spec.h"
#include "api/routes.h"
#include "geometry/io/gltf.h"
#include "geometry/io/number_text.h"
#include "geometry/mesh/normals.h"
#include "geometry/subdivision/subdivide.h"

namespace surfaced::api::operations {

double ms_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

std::string format_ms(double ms) { return number_text(std::round(ms * 1000) / 1000); }

std::string format_double(double value) { return number_text(value); }

std::string media_type_of(std::string_view content_type) {
    const auto semicolon = content_type.find(';');
    std::string_view type = content_type.substr(0, semicolon);
    while (!type.empty() && std::isspace(static_cast<unsigned char>(type.front()))) type.remove_prefix(1);
    while (!type.empty() && std::isspace(static_cast<unsigned char>(type.back()))) type.remove_suffix(1);
    std::string out(type);
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
    return out;
}

std::string accepted_mesh_media_types() {
    std::string out = "application/json";
    for (const auto& entry : kMeshMediaTypes) out += ", " + std::string(entry.name);
    return out + ", application/octet-stream (format detected from the content)" +
           std::string(multipart_media_type_note());
}

std::optional<MeshFormat> mesh_format_for(const std::string& media_type, std::string_view body) {
    if (media_type == "application/octet-stream") return sniff_format(body);
    if (auto format = format_from_media_type(media_type)) return format;
    return enum_from_name(kMeshMediaTypes, media_type);
}

std::string_view output_media_type(OutputFormat format) {
    switch (format) {
        case OutputFormat::Glb: return "model/gltf-binary";
        case OutputFormat::Gltf: return "model/gltf+json";
        case OutputFormat::Obj: return "model/obj";
        case OutputFormat::Ply: return "application/ply";
        case OutputFormat::Json: return "application/json";
        case OutputFormat::Stl: return "model/stl";
        case OutputFormat::Off: return "model/off";
    }
    return "application/octet-stream";
}

ApiError geometry_error(const GeoError& error, Source source) {
    ApiError out = from_geo_error(error);
    if (source != Source::Json || error.element < 0) return out;
    const std::string index = "[" + std::to_string(error.element) + "]";
    switch (error.element_kind) {
        case ElementKind::Vertex: out.field = "mesh.positions" + index; break;
        case ElementKind::Face: out.field = "mesh.faces" + index; break;
        case ElementKind::Crease: out.field = "creases" + index; break;
        case ElementKind::Corner: out.field = "corners" + index; break;
        case ElementKind::Hole: out.field = "holes" + index; break;
        case ElementKind::None: break;
    }
    return out;
}

ApiError geometry_error(const GeoError& error, Source source, const ReadReport& read) {
    ApiError out = geometry_error(error, source);
    if (source != Source::File || out.line || error.element_kind != ElementKind::Face || error.element < 0 ||
        static_cast<std::uint64_t>(error.element) >= read.face_lines.size())
        return out;
    const std::uint32_t line = read.face_lines[static_cast<std::size_t>(error.element)];
    out.line = line;
    out.detail = "line " + std::to_string(line) + ": " + out.detail;
    return out;
}

ApiResult<std::int64_t> parse_integer_parameter(const std::string& name, const std::string& text) {
    std::int64_t value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size())
        return make_problem(Problem::InvalidField,
                            "query parameter " + name + " must be an integer, got \"" + text + "\"", name);
    return value;
}

ApiResult<double> parse_number_parameter(const std::string& name, const std::string& text) {
    double value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size() || !std::isfinite(value))
        return make_problem(Problem::InvalidField,
                            "query parameter " + name + " must be a finite number, got \"" + text + "\"", name);
    return value;
}

ApiResult<bool> parse_bool_parameter(const std::string& name, const std::string& text) {
    if (text == "true" || text == "1") return true;
    if (text == "false" || text == "0") return false;
    return make_problem(Problem::InvalidField,
                        "query parameter " + name + " must be true or false, got \"" + text + "\"", name);
}

std::optional<ApiError> check_body(const ApiRequest& request, const Limits& limits, std::string& media_type,
                                   std::string_view accepted) {
    if (request.body.size() > limits.max_body_bytes)
        return make_problem(Problem::PayloadTooLarge, "request body is " + std::to_string(request.body.size()) +
                                                          " bytes; the limit is " +
                                                          std::to_string(limits.max_body_bytes) + " bytes");
    if (request.body.empty())
        return make_problem(Problem::EmptyBody, "the request body is empty; " + request.method + " " + request.path +
                                                    " needs one, as " + std::string(accepted));
    media_type = media_type_of(request.content_type);
    if (media_type.empty())
        return make_problem(Problem::UnsupportedMediaType,
                            "a Content-Type is required; accepted: " + std::string(accepted));
    return std::nullopt;
}

std::string_view multipart_media_type_note() { return ", multipart/form-data (one file part, options as fields)"; }

std::string media_type_for_filename(std::string_view filename) {
    if (auto format = format_from_extension(filename)) return std::string(enum_name(kMeshMediaTypes, *format));
    const std::size_t dot = filename.rfind('.');
    if (dot == std::string_view::npos) return {};
    std::string ext(filename.substr(dot + 1));
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext == "json") return "application/json";
    if (ext == "bez" || ext == "bpt" || ext == "bbp") return "application/x-geomview-bez";
    if (ext == "xyz" || ext == "pts") return "text/x-xyz";
    if (ext == "txt") return "text/plain";
    return {};
}

bool reads_mesh_media_type(std::string_view media_type) {
    return media_type == "application/json" || media_type == "application/octet-stream" ||
           format_from_media_type(media_type) || enum_from_name(kMeshMediaTypes, media_type);
}

namespace {

//! The media type of the file part: its own when the endpoint reads it (the generic application/octet-stream and
//! text/plain, which browsers and curl send for files they do not know, give way to a known extension), else the
//! extension's, else application/octet-stream (the format then sniffed where the endpoint does so).
}  // namespace

std::string file_part_media_type(const MultipartPart& part, ReadsMediaType reads) {
    const std::string declared = media_type_of(part.content_type);
    const bool generic = declared == "application/octet-stream" || declared == "text/plain";
    if (!declared.empty() && !generic && reads(declared)) return declared;
    const std::string by_name = media_type_for_filename(part.filename.value_or(""));
    if (!by_name.empty() && reads(by_name)) return by_name;
    if (!declared.empty()) return declared;
    return "application/octet-stream";
}

std::optional<ApiError> check_upload(const ApiRequest& request, const Limits& limits, std::string_view accepted,
                                     ReadsMediaType reads, Upload& out) {
    out.request = &request;
    if (auto error = check_body(request, limits, out.media_type, accepted)) return error;
    if (out.media_type != "multipart/form-data") return std::nullopt;
    auto boundary = multipart_boundary(request.content_type);
    if (!boundary) return std::move(boundary.error());
    auto parts = parse_multipart(request.body, boundary.value());
    if (!parts) return std::move(parts.error());
    const MultipartPart* file = nullptr;
    ApiRequest& form = out.form;
    form.method = request.method;
    form.path = request.path;
    form.path_params = request.path_params;
    form.headers = request.headers;
    form.query = request.query;
    for (const MultipartPart& part : parts.value()) {
        if (part.filename || part.name == "file") {
            if (file)
                return make_problem(Problem::MalformedMultipart, "two file parts, \"" + file->name + "\" and \"" +
                                                                     part.name + "\": send exactly one file");
            file = &part;
            continue;
        }
        if (request.query.count(part.name))
            return make_problem(Problem::InvalidField,
                                "option " + part.name + " is given both as a query parameter and as a form field",
                                part.name);
        form.query.emplace(part.name, std::string(part.body));
        form.form_fields.insert(part.name);
    }
    if (!file)
        return make_problem(Problem::MalformedMultipart,
                            "no file part: send the file as a part with a filename (curl -F file=@mesh.obj), the "
                            "options as the other parts");
    if (file->body.empty())
        return make_problem(Problem::EmptyBody,
                            "the file part \"" + file->name + "\"" +
                                (file->filename && !file->filename->empty() ? " (" + *file->filename + ")"
                                                                            : std::string(" (no file chosen?)")) +
                                " is empty");
    form.body = file->body;
    out.media_type = file_part_media_type(*file, reads);
    form.content_type = out.media_type;
    out.request = &form;
    return std::nullopt;
}

ApiError worded_for_form(const ApiRequest& request, ApiError error) {
    if (request.form_fields.empty() || !error.field) return error;
    const std::string name = error.field->substr(0, error.field->find('['));
    if (!request.form_fields.count(name)) return error;
    const auto replace_all = [&](std::string_view from, std::string_view to) {
        for (std::size_t at = error.detail.find(from); at != std::string::npos;
             at = error.detail.find(from, at + to.size()))
            error.detail.replace(at, from.size(), to);
    };
    replace_all("unknown query parameters ", "unknown form fields ");
    replace_all("unknown query parameter ", "unknown form field ");
    replace_all("query parameter " + name + " ", "form field " + name + " ");
    replace_all("query parameter " + name + ":", "form field " + name + ":");
    if (error.code == "unknown_parameter") error.title = "Unknown form field";
    return error;
}

std::optional<ApiError> negotiate_output_format(const ApiRequest& request, OutputOptions& out) {
    if (out.format_given) return std::nullopt;
    std::string accept;  // several Accept headers make one list (RFC 9110 section 5.3)
    for (auto [it, end] = request.headers.equal_range("accept"); it != end; ++it)
        accept += (accept.empty() ? "" : ", ") + it->second;
    if (accept.empty()) return std::nullopt;
    const options::OptionSpec* format_option = nullptr;
    for (const options::OperationOptions& operation : options::operations())
        if (match_path(operation.path, request.path)) {
            format_option = options::find_option(operation, "format");
            if (format_option) break;
        }
    if (!format_option) return std::nullopt;
    std::vector<OutputFormat> formats;
    std::vector<std::string_view> media_types;
    std::size_t preferred = 0;
    std::string_view default_name = format_option->default_json;
    if (default_name.size() >= 2 && default_name.front() == '"')
        default_name = default_name.substr(1, default_name.size() - 2);
    for (std::string_view name : format_option->values) {
        const auto format = enum_from_name(kOutputFormatNames, name);
        if (!format) continue;
        if (name == default_name) preferred = formats.size();
        formats.push_back(*format);
        media_types.push_back(output_media_type(*format));
    }
    if (const auto chosen = negotiate_media_type(accept, media_types, preferred)) {
        out.format = formats[*chosen];
        return std::nullopt;
    }
    std::string offered;
    for (std::string_view type : media_types) offered += (offered.empty() ? "" : ", ") + std::string(type);
    const std::string shown = accept.size() > 200 ? accept.substr(0, 200) + "..." : accept;
    return make_problem(Problem::NotAcceptable,
                        "the Accept header (\"" + shown + "\") accepts none of the media types " + request.method +
                            " " + request.path + " answers with: " + offered + " (or name one with format)");
}

std::optional<ApiError> reject_query_with_json(const ApiRequest& request) {
    if (request.query.empty()) return std::nullopt;
    const std::string& name = request.query.begin()->first;
    return make_problem(
        Problem::UnknownParameter,
        "query parameters are not accepted with a JSON body (options go in the body), got \"" + name + "\"", name);
}

std::optional<ApiError> check_json_only_body(const ApiRequest& request, const Limits& limits,
                                             std::string_view operation) {
    std::string media_type;
    if (auto error = check_body(request, limits, media_type, "application/json")) return error;
    if (media_type != "application/json")
        return make_problem(Problem::UnsupportedMediaType,
                            std::string(operation) + " takes application/json" +
                                (media_type.empty() ? std::string() : ", not \"" + media_type + "\""));
    return reject_query_with_json(request);
}

ApiResult<PolygonMesh> read_uploaded_mesh(const ApiRequest& request, const std::string& media_type,
                                          const Limits& limits, MeshRules rules, ReadReport* report) {
    const auto format = mesh_format_for(media_type, request.body);
    if (!format) {
        const std::string detail =
            media_type == "application/octet-stream"
                ? "could not recognise the mesh format from the content; send a specific Content-Type (" +
                      accepted_mesh_media_types() + ")"
                : "Content-Type \"" + media_type + "\" is not accepted; accepted: " + accepted_mesh_media_types();
        return make_problem(Problem::UnsupportedMediaType, detail);
    }
    ReadOptions read_options;
    read_options.max_vertices = static_cast<std::size_t>(limits.max_input_vertices);
    read_options.max_faces = static_cast<std::size_t>(limits.max_input_faces);
    read_options.allow_repeated_vertices = rules == MeshRules::Subdivision;
    auto read = read_mesh(request.body, *format, read_options, report);
    if (!read) return geometry_error(read.error(), Source::File);
    return std::move(read).value();
}

std::optional<ApiError> check_input_budget(const PolygonMesh& mesh, const Limits& limits) {
    if (mesh.face_count() > limits.max_input_faces || mesh.vertex_count() > limits.max_input_vertices)
        return make_problem(Problem::BudgetExceeded, "the mesh has " + std::to_string(mesh.vertex_count()) +
                                                         " vertices and " + std::to_string(mesh.face_count()) +
                                                         " faces; the limits are " +
                                                         std::to_string(limits.max_input_vertices) + " and " +
                                                         std::to_string(limits.max_input_faces));
    return std::nullopt;
}

std::optional<ApiError> refuse_unknown_mesh_format(const ApiRequest& request, const std::string& media_type,
                                                   const Limits& limits) {
    if (mesh_format_for(media_type, request.body)) return std::nullopt;
    auto refused = read_uploaded_mesh(request, media_type, limits);  // the 415, worded in one place
    return std::move(refused.error());
}

std::optional<ApiError> check_mesh_input(const PolygonMesh& mesh, const Limits& limits, Source source,
                                         MeshRules rules) {
    if (auto error = check_input_budget(mesh, limits)) return error;
    const Status valid = rules == MeshRules::Subdivision ? validate_for_subdivision(mesh) : validate(mesh);
    if (!valid) return geometry_error(valid.error(), source);
    return std::nullopt;
}

std::optional<ApiError> check_triangulated_budget(const PolygonMesh& mesh, const Limits& limits) {
    const std::uint64_t triangles = mesh.face_indices.size() - 2 * mesh.face_count();
    if (triangles > limits.max_input_faces)
        return make_problem(Problem::BudgetExceeded, "the mesh triangulates to " + std::to_string(triangles) +
                                                         " triangles; the limit is " +
                                                         std::to_string(limits.max_input_faces));
    return std::nullopt;
}

bool float32_format(OutputFormat format) {
    return format == OutputFormat::Glb || format == OutputFormat::Gltf || format == OutputFormat::Stl;
}

bool normals_format(OutputFormat format) { return format != OutputFormat::Stl && format != OutputFormat::Off; }

bool output_normals(const OutputOptions& out) { return normals_format(out.format) && out.normals.value_or(true); }

std::optional<ApiError> check_float32_range(const std::vector<Vec3>& positions, OutputFormat format,
                                            std::string_view element, std::optional<std::string_view> field) {
    if (!float32_format(format)) return std::nullopt;
    constexpr double kMax = std::numeric_limits<float>::max();
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const Vec3& p = positions[i];
        const double coordinates[3] = {p.x, p.y, p.z};
        for (int axis = 0; axis < 3; ++axis) {
            if (std::abs(coordinates[axis]) <= kMax) continue;
            const std::string format_name(enum_name(kOutputFormatNames, format));
            ApiError error = make_problem(Problem::CoordinateOutOfRange,
                                          std::string(element) + " " + std::to_string(i) + " has " + "xyz"[axis] +
                                              " = " + format_double(coordinates[axis]) +
                                              ", beyond the float32 range (+-3.4028235e38) of format \"" + format_name +
                                              "\"; format obj, ply, off or json keeps doubles");
            if (field) error.field = std::string(*field) + "[" + std::to_string(i) + "]";
            return error;
        }
    }
    return std::nullopt;
}

std::optional<ApiError> check_deadline_before_encoding(const Cancel& cancel) {
    if (!cancel.requested()) return std::nullopt;
    return from_geo_error(GeoError{ErrorCode::Cancelled, "the request's compute deadline passed before encoding"});
}

Headers mesh_count_headers(std::size_t input_vertices, std::size_t input_faces, std::size_t output_vertices,
                           std::size_t output_faces) {
    return {
        {"X-Input-Vertices", std::to_string(input_vertices)},
        {"X-Input-Faces", std::to_string(input_faces)},
        {"X-Output-Vertices", std::to_string(output_vertices)},
        {"X-Output-Faces", std::to_string(output_faces)},
    };
}

void append_read_headers(Headers& headers, const ReadReport& read) {
    if (read.skipped_primitives > 0)
        headers.emplace_back("X-Skipped-Primitives", std::to_string(read.skipped_primitives));
}

void append_timing_headers(Headers& headers, const Timing& timing) {
    const Clock::time_point end = timing.stages.empty() ? timing.start : timing.stages.back().second;
    std::string server_timing;
    Clock::time_point from = timing.start;
    for (const auto& [name, to] : timing.stages) {
        server_timing += std::string(name) + ";dur=" + format_ms(ms_between(from, to)) + ", ";
        from = to;
    }
    server_timing += "total;dur=" + format_ms(ms_between(timing.start, end));
    headers.emplace_back("X-Elapsed-Ms", format_ms(ms_between(timing.start, end)));
    headers.emplace_back("Server-Timing", std::move(server_timing));
}

std::optional<ApiError> check_output_options(const OutputOptions& out, Source source) {
    const auto field = [&](std::string_view leaf) {
        return (source == Source::Json ? "output." : "") + std::string(leaf);
    };
    const bool gltf = out.format == OutputFormat::Glb || out.format == OutputFormat::Gltf;  // binary or text
    const std::string format(enum_name(kOutputFormatNames, out.format));
    if (out.draco && !gltf)
        return make_problem(Problem::InvalidField,
                            "compression applies only to formats \"glb\" and \"gltf\", not \"" + format + "\"",
                            field("compression"));
    // (its range, 1..24, is the option table's)
    if (out.quantize_position && (!gltf || !out.draco.value_or(true)))
        return make_problem(Problem::InvalidField,
                            "quantize_position applies only to formats \"glb\" and \"gltf\" with compression \"draco\"",
                            field("quantize_position"));
    if (out.normals.value_or(false) && !normals_format(out.format))
        return make_problem(Problem::InvalidField,
                            "normals: format \"" + format + "\" has no vertex normals" +
                                (out.format == OutputFormat::Stl ? " (STL writes a facet normal per triangle)" : "") +
                                "; leave normals out or set it to false",
                            field("normals"));
    return std::nullopt;
}

void prepare_normals(PolygonMesh& mesh, const OutputOptions& out) {
    if (!output_normals(out))
        mesh.normals.clear();
    else if (mesh.normals.size() != mesh.positions.size())  // none, or not one per vertex: computed
        mesh.normals = compute_vertex_normals(mesh);
}

ApiResult<std::string> encode_mesh_file(PolygonMesh& mesh, const OutputOptions& out, Source source,
                                        VertexColors colors) {
    const bool normals = output_normals(out);
    switch (out.format) {
        case OutputFormat::Glb:
        case OutputFormat::Gltf: {
            if (auto error = check_float32_range(mesh.positions, out.format, "output vertex")) return std::move(*error);
            GltfOptions gltf;
            gltf.draco = out.draco.value_or(true);
            if (out.quantize_position) gltf.quantize_position = static_cast<int>(*out.quantize_position);
            gltf.normals = normals;
            gltf.vertex_colors = colors.colors;
            gltf.vertex_alpha = colors.alpha;
            prepare_normals(mesh, out);
            auto encoded = out.format == OutputFormat::Glb ? write_glb(mesh, gltf) : write_gltf(mesh, gltf);
            if (!encoded) return geometry_error(encoded.error(), source);
            return std::move(encoded).value();
        }
        case OutputFormat::Obj: {
            ObjWriteOptions obj;
            obj.write_normals = normals;
            obj.vertex_colors = colors.colors;
            prepare_normals(mesh, out);
            return write_obj(mesh, obj);
        }
        case OutputFormat::Ply:
            prepare_normals(mesh, out);  // write_ply writes normals exactly when the mesh has them
            return write_ply(mesh, PlyEncoding::BinaryLittleEndian, colors.colors, colors.alpha);
        case OutputFormat::Stl:
            if (auto error = check_float32_range(mesh.positions, out.format, "output vertex")) return std::move(*error);
            return write_stl(mesh);
        case OutputFormat::Off: return write_off(mesh);
        case OutputFormat::Json: break;
    }
    return make_problem(Problem::Internal, "JSON output is encoded by the operation");
}

}  // namespace surfaced::api::operations
