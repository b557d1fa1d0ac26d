// Stanford PLY 1.0 reader (ascii, binary_little_endian, binary_big_endian) and writer (ascii, binary little endian).
// Reading is driven by the header: every element is walked property by property, so elements and properties we
// do not use (colours, texture lists, edges, materials...) are skipped exactly, whatever their types.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/io/format_common.h"
#include "geometry/io/mesh_io.h"
#include "geometry/io/ply_header.h"
#include "geometry/io/text_scanner.h"

namespace surfaced {
namespace {

using io_detail::error_at_line;
using io_detail::error_at_offset;
using io_detail::NumberStatus;
using io_detail::quote;
using namespace io_detail::ply;

//! Where the vertex and face data we keep sit among each element's properties.
struct Layout {
    int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1;
    int indices = -1;
};

class PlyReader : io_detail::ply::BinaryCursor {
public:
    PlyReader(std::string_view bytes, io_detail::TextEncoding encoding, const ReadOptions& options, ReadReport* report)
        : BinaryCursor(bytes), encoding_(encoding), options_(options), report_(report) {}

    Result<PolygonMesh> read() {
        auto parsed = parse_header(bytes_, options_, encoding_);
        if (!parsed) return parsed.error();
        header_ = std::move(*parsed);

        const PlyElement* vertex = nullptr;
        const PlyElement* face = nullptr;
        for (const auto& e : header_.elements) {
            if (e.name == "vertex") vertex = &e;
            if (e.name == "face") face = &e;
        }
        if (!vertex)
            return error_at_line(ErrorCode::ParseError, header_.body_line - 1, "no vertex element in the header");
        if (!face || face->count == 0) return error_at_line(ErrorCode::ParseError, header_.body_line - 1, "no faces");
        layout_.x = vertex->find("x");
        layout_.y = vertex->find("y");
        layout_.z = vertex->find("z");
        for (const char* name : {"x", "y", "z"}) {
            const int i = vertex->find(name);
            if (i < 0)
                return error_at_line(ErrorCode::ParseError, vertex->line,
                                     std::string("vertex element has no '") + name + "' property");
            if (vertex->properties[static_cast<std::size_t>(i)].is_list)
                return error_at_line(ErrorCode::ParseError, vertex->line,
                                     std::string("vertex property '") + name + "' is a list");
        }
        layout_.nx = vertex->find("nx");
        layout_.ny = vertex->find("ny");
        layout_.nz = vertex->find("nz");
        read_normals_ = layout_.nx >= 0 && layout_.ny >= 0 && layout_.nz >= 0 &&
                        !vertex->properties[static_cast<std::size_t>(layout_.nx)].is_list &&
                        !vertex->properties[static_cast<std::size_t>(layout_.ny)].is_list &&
                        !vertex->properties[static_cast<std::size_t>(layout_.nz)].is_list;
        layout_.indices = face->find("vertex_indices");
        if (layout_.indices < 0) layout_.indices = face->find("vertex_index");
        if (layout_.indices < 0)
            return error_at_line(ErrorCode::ParseError, face->line, "face element has no vertex_indices list");
        const PlyProperty& list = face->properties[static_cast<std::size_t>(layout_.indices)];
        if (!list.is_list) return error_at_line(ErrorCode::ParseError, face->line, "face vertex_indices is not a list");
        if (!is_integer(list.type))
            return error_at_line(ErrorCode::ParseError, face->line, "face vertex_indices items are not integers");
        vertex_count_ = vertex->count;

        // parse_header bounded both counts by the bytes present
        mesh_.positions.reserve(vertex->count);
        if (read_normals_) mesh_.normals.reserve(vertex->count);
        mesh_.face_offsets.reserve(face->count + 1);
        mesh_.face_indices.reserve(face->count * 3);

        if (header_.encoding == PlyEncodingIn::Ascii) {
            io_detail::TokenReader tokens(bytes_, header_.body_offset, '\0', header_.body_line);
            for (const auto& e : header_.elements)
                if (auto error = read_ascii_element(e, tokens)) return std::move(*error);
        } else {
            pos_ = header_.body_offset;
            big_endian_ = header_.encoding == PlyEncodingIn::BinaryBigEndian;
            for (const auto& e : header_.elements)
                if (auto error = read_binary_element(e)) return std::move(*error);
        }
        // Normals are optional data: a file with NaN normals (some exporters write them for degenerate faces)
        // still gives its geometry, without normals.
        if (!normals_finite_) mesh_.normals.clear();
        return std::move(mesh_);
    }

private:
    enum class Role { Vertex, Face, Other };
    Role role(const PlyElement& e) const {
        if (e.name == "vertex") return Role::Vertex;
        if (e.name == "face") return Role::Face;
        return Role::Other;
    }

    // ---- binary
    std::optional<GeoError> read_binary_element(const PlyElement& e) {
        const Role r = role(e);
        std::vector<Index> face, scratch;
        for (std::uint64_t item = 0; item < e.count; ++item) {
            const std::size_t item_offset = pos_;
            Vec3 p, n;
            for (std::size_t k = 0; k < e.properties.size(); ++k) {
                const PlyProperty& prop = e.properties[k];
                const int ki = static_cast<int>(k);
                const unsigned char* bytes = nullptr;
                if (!prop.is_list) {
                    const std::size_t size = type_size(prop.type);
                    if (!take(size, bytes)) return truncated(e, item);
                    if (r != Role::Vertex) continue;
                    const double value = bits_to_double(load_bits(bytes, size, big_endian_), prop.type);
                    if (ki == layout_.x)
                        p.x = value;
                    else if (ki == layout_.y)
                        p.y = value;
                    else if (ki == layout_.z)
                        p.z = value;
                    else if (ki == layout_.nx)
                        n.x = value;
                    else if (ki == layout_.ny)
                        n.y = value;
                    else if (ki == layout_.nz)
                        n.z = value;
                    continue;
                }
                const std::size_t count_size = type_size(prop.count_type);
                if (!take(count_size, bytes)) return truncated(e, item);
                const std::int64_t count = bits_to_int(load_bits(bytes, count_size, big_endian_), prop.count_type);
                const std::size_t list_offset = pos_ - count_size;
                if (count < 0)
                    return error_at_offset(ErrorCode::ParseError, static_cast<std::int64_t>(list_offset),
                                           "negative list length " + std::to_string(count));
                const bool is_face_list = r == Role::Face && ki == layout_.indices;
                if (is_face_list) {
                    if (auto error = check_face_size(count, item, list_offset, -1)) return error;
                }
                const std::size_t item_size = type_size(prop.type);
                if (static_cast<std::uint64_t>(count) > (bytes_.size() - pos_) / item_size) return truncated(e, item);
                take(static_cast<std::size_t>(count) * item_size, bytes);
                if (!is_face_list) continue;
                face.clear();
                for (std::int64_t i = 0; i < count; ++i) {
                    const std::int64_t v =
                        bits_to_int(load_bits(bytes + i * item_size, item_size, big_endian_), prop.type);
                    if (v < 0 || static_cast<std::uint64_t>(v) >= vertex_count_)
                        return error_at_offset(ErrorCode::IndexOutOfRange,
                                               static_cast<std::int64_t>(list_offset + count_size + i * item_size),
                                               "face " + std::to_string(item) + " index " + std::to_string(v) +
                                                   " out of range (" + std::to_string(vertex_count_) + " vertices)");
                    face.push_back(static_cast<Index>(v));
                }
            }
            if (r == Role::Vertex) {
                if (auto error = add_vertex(p, n, item, static_cast<std::int64_t>(item_offset), -1)) return error;
            } else if (r == Role::Face) {
                if (auto error = add_face(face, scratch, item, static_cast<std::int64_t>(item_offset), -1))
                    return error;
            }
        }
        return std::nullopt;
    }

    // ---- ascii
    std::optional<GeoError> read_ascii_element(const PlyElement& e, io_detail::TokenReader& tokens) {
        const Role r = role(e);
        std::vector<Index> face, scratch;
        std::string_view token;
        for (std::uint64_t item = 0; item < e.count; ++item) {
            Vec3 p, n;
            face.clear();
            std::int64_t item_line = -1;
            auto next = [&](std::string_view& out) -> std::optional<GeoError> {
                if (!tokens.next(out))
                    return error_at_line(ErrorCode::ParseError, tokens.line(),
                                         "unexpected end of file in " + quote(e.name) + " element " +
                                             std::to_string(item) + " of " + std::to_string(e.count));
                if (item_line < 0) item_line = tokens.line();
                return std::nullopt;
            };
            for (std::size_t k = 0; k < e.properties.size(); ++k) {
                const PlyProperty& prop = e.properties[k];
                const int ki = static_cast<int>(k);
                if (auto error = next(token)) return error;
                if (!prop.is_list) {
                    if (r != Role::Vertex) continue;
                    double* target = ki == layout_.x    ? &p.x
                                     : ki == layout_.y  ? &p.y
                                     : ki == layout_.z  ? &p.z
                                     : ki == layout_.nx ? &n.x
                                     : ki == layout_.ny ? &n.y
                                     : ki == layout_.nz ? &n.z
                                                        : nullptr;
                    if (target && io_detail::parse_double(token, *target) != NumberStatus::Ok)
                        return error_at_line(ErrorCode::ParseError, tokens.line(),
                                             "vertex value " + quote(token) + " is not a number");
                    continue;
                }
                std::int64_t count = 0;
                if (io_detail::parse_int(token, count) != NumberStatus::Ok || count < 0)
                    return error_at_line(ErrorCode::ParseError, tokens.line(),
                                         "list length " + quote(token) + " is not a non-negative integer");
                const bool is_face_list = r == Role::Face && ki == layout_.indices;
                if (is_face_list) {
                    if (auto error = check_face_size(count, item, -1, tokens.line())) return error;
                }
                // Count tokens one by one: a huge declared length just runs into the end of the file.
                for (std::int64_t i = 0; i < count; ++i) {
                    if (auto error = next(token)) return error;
                    if (!is_face_list) continue;
                    std::int64_t v = 0;
                    const auto status = io_detail::parse_int(token, v);
                    if (status == NumberStatus::Invalid)
                        return error_at_line(ErrorCode::ParseError, tokens.line(),
                                             "face index " + quote(token) + " is not an integer");
                    if (status == NumberStatus::OutOfRange || v < 0 || static_cast<std::uint64_t>(v) >= vertex_count_)
                        return error_at_line(ErrorCode::IndexOutOfRange, tokens.line(),
                                             "face index " + std::string(token) + " out of range (" +
                                                 std::to_string(vertex_count_) + " vertices)");
                    face.push_back(static_cast<Index>(v));
                }
            }
            if (r == Role::Vertex) {
                if (auto error = add_vertex(p, n, item, -1, item_line)) return error;
            } else if (r == Role::Face) {
                if (auto error = add_face(face, scratch, item, -1, item_line)) return error;
            }
        }
        return std::nullopt;
    }

    // ---- shared
    GeoError located(ErrorCode code, std::int64_t offset, std::int64_t line, const std::string& what) const {
        return line >= 0 ? error_at_line(code, line, what) : error_at_offset(code, offset, what);
    }

    std::optional<GeoError> check_face_size(std::int64_t count, std::uint64_t item, std::int64_t offset,
                                            std::int64_t line) {
        if (static_cast<std::uint64_t>(count) > options_.max_face_size)
            return located(ErrorCode::BudgetExceeded, offset, line,
                           "face " + std::to_string(item) + " has " + std::to_string(count) +
                               " vertices, more than max_face_size (" + std::to_string(options_.max_face_size) + ")");
        if (count < 3)
            return located(
                ErrorCode::DegenerateFace, offset, line,
                "face " + std::to_string(item) + " has " + std::to_string(count) + " vertices (at least 3 needed)");
        return std::nullopt;
    }

    std::optional<GeoError> add_vertex(const Vec3& p, const Vec3& n, std::uint64_t item, std::int64_t offset,
                                       std::int64_t line) {
        if (!is_finite(p))
            return located(ErrorCode::NonFinite, offset, line,
                           "vertex " + std::to_string(item) + " has a non-finite coordinate");
        mesh_.positions.push_back(p);
        if (read_normals_) {
            normals_finite_ = normals_finite_ && is_finite(n);
            mesh_.normals.push_back(n);
        }
        return std::nullopt;
    }

    std::optional<GeoError> add_face(const std::vector<Index>& face, std::vector<Index>& scratch, std::uint64_t item,
                                     std::int64_t offset, std::int64_t line) {
        if (!options_.allow_repeated_vertices) {
            if (auto dup = io_detail::repeated_vertex(face, scratch))
                return located(
                    ErrorCode::DegenerateFace, offset, line,
                    "face " + std::to_string(item) + " uses vertex " + std::to_string(*dup) + " more than once");
        }
        if (mesh_.face_indices.size() + face.size() > io_detail::kMaxIndexCount)
            return located(ErrorCode::BudgetExceeded, offset, line, "more than 2^32 face corners");
        mesh_.add_face(face);
        if (line >= 0) io_detail::record_face_line(report_, line);  // ascii: the line of the face's first token
        return std::nullopt;
    }

    io_detail::TextEncoding encoding_;
    const ReadOptions& options_;
    ReadReport* report_;
    PlyHeader header_;
    Layout layout_;
    bool read_normals_ = false;
    bool normals_finite_ = true;
    bool big_endian_ = false;
    std::uint64_t vertex_count_ = 0;
    PolygonMesh mesh_;
};

void store_le(std::string& out, std::uint64_t bits, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) out += static_cast<char>((bits >> (8 * i)) & 0xff);
}

}  // namespace

Result<PolygonMesh> read_ply(std::string_view bytes, const ReadOptions& options) {
    return read_ply(bytes, options, nullptr);
}

Result<PolygonMesh> read_ply(std::string_view bytes, const ReadOptions& options, ReadReport* report) {
    return io_detail::with_text(bytes, [&](std::string_view text, io_detail::TextEncoding encoding) {
        return PlyReader(text, encoding, options, report).read();
    });
}

std::string write_ply(const PolygonMesh& mesh, PlyEncoding encoding, std::span<const Color> vertex_colors, bool alpha) {
    using io_detail::append_uint;
    const bool binary = encoding == PlyEncoding::BinaryLittleEndian;
    const bool normals = mesh.has_normals() && mesh.normals.size() == mesh.positions.size();
    const bool colors = !mesh.positions.empty() && vertex_colors.size() == mesh.positions.size();
    const int channels = colors ? (alpha ? 4 : 3) : 0;
    bool big_faces = false;
    for (std::size_t f = 0; f < mesh.face_count() && !big_faces; ++f) big_faces = mesh.face_size(f) > 255;

    std::string out;
    out.reserve(256 + mesh.positions.size() * (normals ? 48 : 24) * (binary ? 1 : 2) + mesh.face_indices.size() * 8 +
                mesh.face_count() * 4);
    out += "ply\nformat ";
    out += binary ? "binary_little_endian" : "ascii";
    out += " 1.0\ncomment written by surfaced\nelement vertex ";
    append_uint(out, mesh.positions.size());
    out += "\nproperty double x\nproperty double y\nproperty double z\n";
    if (normals) out += "property double nx\nproperty double ny\nproperty double nz\n";
    if (colors) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    if (colors && alpha) out += "property uchar alpha\n";
    out += "element face ";
    append_uint(out, mesh.face_count());
    out += big_faces ? "\nproperty list uint uint vertex_indices\n" : "\nproperty list uchar uint vertex_indices\n";
    out += "end_header\n";

    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3& p = mesh.positions[v];
        const Vec3 n = normals ? mesh.normals[v] : Vec3{};
        const double values[6] = {p.x, p.y, p.z, n.x, n.y, n.z};
        const int count = normals ? 6 : 3;
        for (int i = 0; i < count; ++i) {
            if (binary) {
                store_le(out, std::bit_cast<std::uint64_t>(values[i]), 8);
            } else {
                if (i > 0) out += ' ';
                io_detail::append_double(out, values[i], 17);
            }
        }
        if (colors) {
            const Color& c = vertex_colors[v];
            const float rgba[4] = {c.r, c.g, c.b, c.a};
            for (int i = 0; i < channels; ++i) {
                const auto byte = static_cast<unsigned>(std::lround(std::clamp(rgba[i], 0.0f, 1.0f) * 255.0f));
                if (binary) {
                    out += static_cast<char>(byte);
                } else {
                    out += ' ';
                    append_uint(out, byte);
                }
            }
        }
        if (!binary) out += '\n';
    }
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        if (binary) {
            store_le(out, face.size(), big_faces ? 4 : 1);
            for (Index v : face) store_le(out, v, 4);
        } else {
            append_uint(out, face.size());
            for (Index v : face) {
                out += ' ';
                append_uint(out, v);
            }
            out += '\n';
        }
    }
    return out;
}

}  // namespace surfaced
