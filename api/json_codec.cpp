#include "api/json_codec.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "api/json_util.h"
#include "api/options/mesh_params.h"
#include "geometry/io/number_text.h"

namespace surfaced::api {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

//! "positions": [[x, y, z], ...] (or "normals") into `out`.
std::optional<ApiError> decode_vectors(const Json& positions, const std::string& positions_path,
                                       std::vector<Vec3>& out) {
    out.reserve(positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) {
        const Json& p = positions[v];
        if (!p.is_array() || p.size() != 3) {
            const std::string field = index_path(positions_path, v);
            return invalid(field, field + " must be an array of 3 numbers [x, y, z]");
        }
        Vec3 point;
        for (std::size_t k = 0; k < 3; ++k) {
            const Json& c = p[k];
            if (!c.is_number()) {
                const std::string field = index_path(index_path(positions_path, v), k);
                return invalid(field, field + " must be a finite number");
            }
            point[static_cast<int>(k)] = c.get<double>();
            // JSON has no NaN/Inf literals, but 1e999 parses to infinity.
            if (!std::isfinite(point[static_cast<int>(k)])) {
                const std::string field = index_path(index_path(positions_path, v), k);
                return geometry_error(ErrorCode::NonFinite, field, field + " must be a finite number");
            }
        }
        out.push_back(point);
    }
    return std::nullopt;
}

//! "normals": one finite [x, y, z] per position (as the JSON mesh output writes them) into mesh.normals.
std::optional<ApiError> decode_normals(const Json& root, std::string_view path, PolygonMesh& mesh) {
    const auto it = root.find("normals");
    if (it == root.end()) return std::nullopt;
    const std::string normals_path = member_path(path, "normals");
    if (!it->is_array()) return invalid(normals_path, normals_path + " must be an array of [x, y, z]");
    if (it->size() != mesh.positions.size())
        return invalid(normals_path, normals_path + " has " + std::to_string(it->size()) +
                                         " normals; it needs one per position (" +
                                         std::to_string(mesh.positions.size()) + ")");
    return decode_vectors(*it, normals_path, mesh.normals);
}

//! "faces": [[i, j, k, ...], ...] into mesh.face_offsets / face_indices; indices checked against the positions.
std::optional<ApiError> decode_faces(const Json& faces, const std::string& faces_path, PolygonMesh& mesh) {
    const std::size_t nv = mesh.positions.size();
    mesh.face_offsets.reserve(faces.size() + 1);
    mesh.face_indices.reserve(faces.size() * 4);
    for (std::size_t f = 0; f < faces.size(); ++f) {
        const Json& face = faces[f];
        const std::string face_field = index_path(faces_path, f);
        if (!face.is_array()) return invalid(face_field, face_field + " must be an array of vertex indices");
        if (face.size() < 3)
            return geometry_error(ErrorCode::DegenerateFace, face_field,
                                  face_field + " has " + std::to_string(face.size()) + " vertices (at least 3 needed)");
        for (std::size_t k = 0; k < face.size(); ++k) {
            const Json& index = face[k];
            if (!index.is_number_unsigned()) {
                // Negative integers are number_integer, fractions are number_float: both are wrong here.
                const std::string field = index_path(face_field, k);
                return invalid(field, field + " must be a non-negative integer vertex index");
            }
            const auto value = index.get<std::uint64_t>();
            if (value >= nv) {
                const std::string field = index_path(face_field, k);
                return geometry_error(ErrorCode::IndexOutOfRange, field,
                                      field + ": vertex " + std::to_string(value) + " out of range (" +
                                          std::to_string(nv) + " vertices)");
            }
            mesh.face_indices.push_back(static_cast<Index>(value));
        }
        mesh.face_offsets.push_back(static_cast<Index>(mesh.face_indices.size()));
    }
    return std::nullopt;
}

//! Optional face-varying texture coordinates: "uvs": [[u, v], ...] and "uv_faces" parallel to "faces" (one uv index
//! per face corner); both or neither. Decoded after the faces, whose sizes the uv faces must match.
std::optional<ApiError> decode_uvs(const Json& root, std::string_view path, const Limits& limits, PolygonMesh& mesh) {
    const auto uvs_it = root.find("uvs");
    const auto uv_faces_it = root.find("uv_faces");
    const std::string uvs_path = member_path(path, "uvs"), uv_faces_path = member_path(path, "uv_faces");
    if ((uvs_it == root.end()) != (uv_faces_it == root.end()))
        return invalid(uvs_it == root.end() ? uvs_path : uv_faces_path,
                       uvs_path + " and " + uv_faces_path +
                           " go together (texture coordinates and, per face corner, their indices)");
    if (uvs_it == root.end()) return std::nullopt;
    const Json& uvs = *uvs_it;
    const Json& uv_faces = *uv_faces_it;
    const std::size_t face_count = mesh.face_count();
    if (!uvs.is_array()) return invalid(uvs_path, uvs_path + " must be an array of [u, v]");
    if (!uv_faces.is_array() || uv_faces.size() != face_count)
        return invalid(uv_faces_path, uv_faces_path + " must be an array with one index array per face (" +
                                          std::to_string(face_count) + ")");
    if (uvs.size() > limits.max_input_vertices * 4)
        return make_problem(Problem::BudgetExceeded, uvs_path + " has too many entries", uvs_path);
    for (std::size_t i = 0; i < uvs.size(); ++i) {
        const Json& uv = uvs[i];
        const std::string field = index_path(uvs_path, i);
        if (!uv.is_array() || uv.size() != 2 || !uv[0].is_number() || !uv[1].is_number())
            return invalid(field, field + " must be an array of 2 numbers [u, v]");
        const Vec2 value{uv[0].get<double>(), uv[1].get<double>()};
        if (!is_finite(value)) return geometry_error(ErrorCode::NonFinite, field, field + " must be finite");
        mesh.uvs.push_back(value);
    }
    for (std::size_t f = 0; f < uv_faces.size(); ++f) {
        const Json& face = uv_faces[f];
        const std::string field = index_path(uv_faces_path, f);
        const std::size_t n = mesh.face_size(f);
        if (!face.is_array() || face.size() != n)
            return invalid(field, field + " must have one uv index per corner of face " + std::to_string(f) + " (" +
                                      std::to_string(n) + ")");
        for (std::size_t k = 0; k < n; ++k) {
            const Json& index = face[k];
            const std::string corner = index_path(field, k);
            if (!index.is_number_unsigned())
                return invalid(corner, corner + " must be a non-negative integer uv index");
            const auto value = index.get<std::uint64_t>();
            if (value >= mesh.uvs.size())
                return geometry_error(ErrorCode::IndexOutOfRange, corner,
                                      corner + ": uv " + std::to_string(value) + " out of range (" +
                                          std::to_string(mesh.uvs.size()) + " uvs)");
            mesh.uv_indices.push_back(static_cast<Index>(value));
        }
    }
    return std::nullopt;
}

ApiResult<PolygonMesh> decode_mesh_value(const Json& root, std::string_view path, const Limits& limits) {
    const std::string mesh_path(path);
    if (!root.is_object())
        return invalid(mesh_path,
                       mesh_path + R"( must be an object {"positions": [[x,y,z],...], "faces": [[i,j,k,...],...]})");
    if (auto error = check_members(root, path, {"positions", "faces", "normals", "uvs", "uv_faces"}))
        return std::move(*error);

    const std::string positions_path = member_path(path, "positions");
    const std::string faces_path = member_path(path, "faces");
    const auto positions_it = root.find("positions");
    const auto faces_it = root.find("faces");
    if (positions_it == root.end())
        return invalid(positions_path, positions_path + " is required (an array of [x, y, z])");
    if (faces_it == root.end())
        return invalid(faces_path, faces_path + " is required (an array of vertex index arrays)");
    const Json& positions = *positions_it;
    const Json& faces = *faces_it;
    if (!positions.is_array()) return invalid(positions_path, positions_path + " must be an array of [x, y, z]");
    if (!faces.is_array()) return invalid(faces_path, faces_path + " must be an array of vertex index arrays");

    // Budgets first: nothing is copied out of the DOM for a mesh we would refuse anyway.
    if (positions.size() > limits.max_input_vertices)
        return make_problem(Problem::BudgetExceeded,
                            positions_path + " has " + std::to_string(positions.size()) + " vertices; the limit is " +
                                std::to_string(limits.max_input_vertices),
                            positions_path);
    if (faces.size() > limits.max_input_faces)
        return make_problem(Problem::BudgetExceeded,
                            faces_path + " has " + std::to_string(faces.size()) + " faces; the limit is " +
                                std::to_string(limits.max_input_faces),
                            faces_path);

    PolygonMesh mesh;
    if (auto error = decode_vectors(positions, positions_path, mesh.positions)) return std::move(*error);
    if (auto error = decode_faces(faces, faces_path, mesh)) return std::move(*error);
    if (auto error = decode_normals(root, path, mesh)) return std::move(*error);
    if (auto error = decode_uvs(root, path, limits, mesh)) return std::move(*error);
    return mesh;
}

ApiResult<double> read_sharpness(const Json& value, const std::string& field) {
    if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < 0)
        return invalid(field, field + " must be a finite number >= 0 (10 or more is infinitely sharp)");
    return value.get<double>();
}

ApiResult<Index> read_index(const Json& value, const std::string& field, std::size_t count, const char* what) {
    if (!value.is_number_unsigned())
        return invalid(field, field + " must be a non-negative integer " + what + " index");
    const auto v = value.get<std::uint64_t>();
    if (v >= count)
        return geometry_error(ErrorCode::IndexOutOfRange, field,
                              field + ": " + what + " " + std::to_string(v) + " out of range (" +
                                  std::to_string(count) + " " + what + (count == 1 ? ")" : "s)"));
    return static_cast<Index>(v);
}

//! "creases": [{"edge": [a, b], "sharpness": s}], "corners": [{"vertex": v, "sharpness": s}], "holes": [f, ...]
std::optional<ApiError> decode_tags(const Json& root, PolygonMesh& mesh) {
    const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
    if (auto it = root.find("creases"); it != root.end()) {
        if (!it->is_array())
            return invalid("creases", R"(creases must be an array of {"edge": [a, b], "sharpness": s})");
        for (std::size_t i = 0; i < it->size(); ++i) {
            const Json& c = (*it)[i];
            const std::string path = index_path("creases", i);
            if (!c.is_object()) return invalid(path, path + R"( must be an object {"edge": [a, b], "sharpness": s})");
            if (auto error = check_members(c, path, {"edge", "sharpness"})) return error;
            const auto edge = c.find("edge");
            const auto sharp = c.find("sharpness");
            if (edge == c.end() || !edge->is_array() || edge->size() != 2)
                return invalid(member_path(path, "edge"),
                               member_path(path, "edge") + " must be [a, b], two vertex indices");
            if (sharp == c.end())
                return invalid(member_path(path, "sharpness"), member_path(path, "sharpness") + " is required");
            auto a = read_index((*edge)[0], index_path(member_path(path, "edge"), 0), nv, "vertex");
            if (!a) return std::move(a.error());
            auto b = read_index((*edge)[1], index_path(member_path(path, "edge"), 1), nv, "vertex");
            if (!b) return std::move(b.error());
            auto s = read_sharpness(*sharp, member_path(path, "sharpness"));
            if (!s) return std::move(s.error());
            mesh.tags.creases.push_back({a.value(), b.value(), s.value()});
        }
    }
    if (auto it = root.find("corners"); it != root.end()) {
        if (!it->is_array()) return invalid("corners", R"(corners must be an array of {"vertex": v, "sharpness": s})");
        for (std::size_t i = 0; i < it->size(); ++i) {
            const Json& c = (*it)[i];
            const std::string path = index_path("corners", i);
            if (!c.is_object()) return invalid(path, path + R"( must be an object {"vertex": v, "sharpness": s})");
            if (auto error = check_members(c, path, {"vertex", "sharpness"})) return error;
            const auto vertex = c.find("vertex");
            const auto sharp = c.find("sharpness");
            if (vertex == c.end())
                return invalid(member_path(path, "vertex"), member_path(path, "vertex") + " is required");
            if (sharp == c.end())
                return invalid(member_path(path, "sharpness"), member_path(path, "sharpness") + " is required");
            auto v = read_index(*vertex, member_path(path, "vertex"), nv, "vertex");
            if (!v) return std::move(v.error());
            auto s = read_sharpness(*sharp, member_path(path, "sharpness"));
            if (!s) return std::move(s.error());
            mesh.tags.corners.push_back({v.value(), s.value()});
        }
    }
    if (auto it = root.find("holes"); it != root.end()) {
        if (!it->is_array()) return invalid("holes", "holes must be an array of face indices");
        for (std::size_t i = 0; i < it->size(); ++i) {
            auto f = read_index((*it)[i], index_path("holes", i), nf, "face");
            if (!f) return std::move(f.error());
            mesh.tags.holes.push_back(f.value());
        }
    }
    return std::nullopt;
}

void append_number(std::string& out, double value) {
    if (!std::isfinite(value)) {  // unreachable for validated meshes; keeps the output valid JSON regardless
        out += "null";
        return;
    }
    append_number_text(out, value);
}

void append_vectors(std::string& out, const std::vector<Vec3>& vectors) {
    for (std::size_t v = 0; v < vectors.size(); ++v) {
        const Vec3& p = vectors[v];
        out += v == 0 ? "[" : ",[";
        append_number(out, p.x);
        out += ',';
        append_number(out, p.y);
        out += ',';
        append_number(out, p.z);
        out += ']';
    }
}

void append_number(std::string& out, std::uint64_t value) {
    char buf[24];
    const auto result = std::to_chars(buf, buf + sizeof buf, value);
    out.append(buf, result.ptr);
}

//! "mesh":{"positions":[...],"faces":[...]} (plus "normals" when the mesh has one per vertex, "uvs" and "uv_faces"
//! when it has texture coordinates), doubles in shortest round-trip form.
void append_mesh(std::string& out, const PolygonMesh& mesh) {
    out += "\"mesh\":{\"positions\":[";
    append_vectors(out, mesh.positions);
    out += "],\"faces\":[";
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        out += f == 0 ? "[" : ",[";
        bool first = true;
        for (Index i : mesh.face(f)) {
            if (!first) out += ',';
            first = false;
            append_number(out, static_cast<std::uint64_t>(i));
        }
        out += ']';
    }
    out += ']';
    if (mesh.has_normals() && mesh.normals.size() == mesh.positions.size()) {
        out += ",\"normals\":[";
        append_vectors(out, mesh.normals);
        out += ']';
    }
    if (mesh.has_uvs()) {
        out += ",\"uvs\":[";
        for (std::size_t i = 0; i < mesh.uvs.size(); ++i) {
            out += i == 0 ? "[" : ",[";
            append_number(out, mesh.uvs[i].x);
            out += ',';
            append_number(out, mesh.uvs[i].y);
            out += ']';
        }
        out += "],\"uv_faces\":[";
        for (std::size_t f = 0; f < mesh.face_count(); ++f) {
            out += f == 0 ? "[" : ",[";
            for (Index i = mesh.face_offsets[f]; i < mesh.face_offsets[f + 1]; ++i) {
                if (i != mesh.face_offsets[f]) out += ',';
                append_number(out, static_cast<std::uint64_t>(mesh.uv_indices[i]));
            }
            out += ']';
        }
        out += ']';
    }
    out += '}';
}

}  // namespace

ApiResult<PolygonMesh> decode_mesh(std::string_view json_text, const Limits& limits, std::string_view path) {
    Json root;
    if (auto error = parse(json_text, root)) return std::move(*error);
    return decode_mesh_value(root, path, limits);
}

std::optional<ApiError> decode_subdivision_tags(const nlohmann::json& body, PolygonMesh& mesh) {
    return decode_tags(body, mesh);
}

ApiResult<PolygonMesh> decode_mesh_json(const nlohmann::json& value, const Limits& limits, std::string_view path) {
    return decode_mesh_value(value, path, limits);
}

ApiResult<SubdivideJsonRequest> decode_subdivide_request(std::string_view body, const Limits& limits) {
    Json root;
    if (auto error = parse(body, root)) return std::move(*error);
    if (!root.is_object())
        return make_problem(Problem::InvalidField,
                            R"(request body must be a JSON object {"mesh": {...}, "scheme": ..., "levels": ...})");
    const auto& spec = *options::operation_options("subdivide");
    if (auto error = check_members(root, "", options::json_members(spec))) return std::move(*error);
    auto values = options::read_json(spec, root);
    if (!values) return std::move(values.error());

    SubdivideJsonRequest request;
    request.params = options::subdivide_params(values.value());
    const auto mesh_it = root.find("mesh");
    if (mesh_it == root.end())
        return invalid("mesh", R"(mesh is required: {"positions": [[x,y,z],...], "faces": [[i,j,k,...],...]})");
    auto mesh = decode_mesh_value(*mesh_it, "mesh", limits);
    if (!mesh) return std::move(mesh.error());
    request.mesh = std::move(mesh.value());
    if (auto error = decode_tags(root, request.mesh)) return std::move(*error);
    return request;
}

std::string encode_mesh_response(const PolygonMesh& mesh, const SubdivideStats& stats) {
    std::string out;
    // About 20 bytes per coordinate and 8 per index: one allocation for typical meshes.
    out.reserve(64 + mesh.positions.size() * 60 + mesh.face_indices.size() * 8 + mesh.face_count() * 4);
    out += '{';
    append_mesh(out, mesh);
    out += ",\"stats\":{\"input_vertices\":";
    append_number(out, static_cast<std::uint64_t>(stats.input_vertices));
    out += ",\"input_faces\":";
    append_number(out, static_cast<std::uint64_t>(stats.input_faces));
    out += ",\"output_vertices\":";
    append_number(out, static_cast<std::uint64_t>(stats.output_vertices));
    out += ",\"output_faces\":";
    append_number(out, static_cast<std::uint64_t>(stats.output_faces));
    out += ",\"scheme\":\"";
    out += enum_name(kSchemeNames, stats.scheme);
    out += "\",\"levels\":";
    append_number(out, static_cast<std::uint64_t>(stats.levels < 0 ? 0 : stats.levels));
    if (stats.target_faces) {
        out += ",\"target_faces\":";
        append_number(out, static_cast<std::uint64_t>(*stats.target_faces));
        out += ",\"achieved_faces\":";
        append_number(out, static_cast<std::uint64_t>(stats.output_faces));
        out += stats.target_met ? ",\"target_met\":true" : ",\"target_met\":false";
    }
    out += ",\"elapsed_ms\":";
    append_number(out, stats.elapsed_ms);
    out += "}}";
    return out;
}

// ---- POST /simplify ------------------------------------------------------------------------------------------

ApiResult<SimplifyJsonRequest> decode_simplify_request(std::string_view body, const Limits& limits) {
    Json root;
    if (auto error = parse(body, root)) return std::move(*error);
    if (!root.is_object())
        return make_problem(
            Problem::InvalidField,
            R"(request body must be a JSON object {"mesh": {...}, "target_faces": N | "ratio": r | "max_error": e})");
    const auto& spec = *options::operation_options("simplify");
    if (auto error = check_members(root, "", options::json_members(spec))) return std::move(*error);
    auto values = options::read_json(spec, root);
    if (!values) return std::move(values.error());
    SimplifyJsonRequest request;
    request.params = options::simplify_params(values.value());
    const auto mesh_it = root.find("mesh");
    if (mesh_it == root.end())
        return invalid("mesh", R"(mesh is required: {"positions": [[x,y,z],...], "faces": [[i,j,k,...],...]})");
    auto mesh = decode_mesh_value(*mesh_it, "mesh", limits);
    if (!mesh) return std::move(mesh.error());
    request.mesh = std::move(mesh.value());
    return request;
}

std::vector<std::pair<std::string_view, std::size_t>> repair_counts(const RepairReport& r) {
    return {{"welded", r.welded},
            {"degenerate", r.degenerate},
            {"duplicate", r.duplicate},
            {"flipped", r.flipped},
            {"nonmanifold_split", r.nonmanifold_split},
            {"small_components", r.small_components},
            {"removed_faces", r.removed_faces},
            {"holes_filled", r.holes_filled},
            {"fill_faces", r.fill_faces},
            {"unreferenced", r.unreferenced},
            {"components", r.components}};
}

std::string encode_repairs(const RepairReport& report) {
    std::string out = "{";
    for (const auto& [name, count] : repair_counts(report)) {
        if (out.size() > 1) out += ',';
        out += '"';
        out += name;
        out += "\":";
        out += std::to_string(count);
    }
    out += '}';
    return out;
}

std::string encode_mesh_with_stats(const PolygonMesh& mesh, std::string_view stats_json) {
    std::string out;
    out.reserve(32 + stats_json.size() + mesh.positions.size() * 60 + mesh.face_indices.size() * 8);
    out += '{';
    append_mesh(out, mesh);
    out += ",\"stats\":";
    out += stats_json;
    out += '}';
    return out;
}

std::string encode_simplify_response(const PolygonMesh& mesh, const SimplifyStats& stats) {
    std::string out;
    out.reserve(256 + mesh.positions.size() * 60 + mesh.face_indices.size() * 8 + mesh.face_count() * 4);
    out += '{';
    append_mesh(out, mesh);
    const auto member = [&](const char* name, auto value) {
        out += ",\"";
        out += name;
        out += "\":";
        append_number(out, value);
    };
    out += ",\"stats\":{\"input_vertices\":";
    append_number(out, static_cast<std::uint64_t>(stats.input_vertices));
    member("input_faces", static_cast<std::uint64_t>(stats.input_faces));
    member("output_vertices", static_cast<std::uint64_t>(stats.output_vertices));
    member("output_faces", static_cast<std::uint64_t>(stats.output_faces));
    out += stats.triangulated ? ",\"triangulated\":true" : ",\"triangulated\":false";
    member("achieved_error", stats.achieved_error);
    member("relative_error", stats.relative_error);
    if (stats.hausdorff) member("hausdorff", *stats.hausdorff);
    if (stats.rms) member("rms", *stats.rms);
    if (stats.repairs) {
        out += ",\"repairs\":";
        out += encode_repairs(*stats.repairs);
    }
    if (stats.target_faces) member("target_faces", static_cast<std::uint64_t>(*stats.target_faces));
    member("achieved_faces", static_cast<std::uint64_t>(stats.achieved_faces));
    out += stats.target_met ? ",\"target_met\":true" : ",\"target_met\":false";
    member("elapsed_ms", stats.elapsed_ms);
    out += "}}";
    return out;
}

}  // namespace surfaced::api
