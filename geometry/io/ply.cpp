// Stanford PLY 1.0 reader (ascii, binary_little_endian, binary_big_endian) and writer (ascii, binary little endian).
// Reading is driven by the header: every element is walked property by property, so elements and properties we
// do not use (colours, texture lists, edges, materials...) are skipped exactly, whatever their types.
#include <bit>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/io/format_common.h"
#include "geometry/io/mesh_io.h"
#include "geometry/io/text_scanner.h"

namespace surfaced {
namespace {

using io_detail::error_at_line;
using io_detail::error_at_offset;
using io_detail::NumberStatus;
using io_detail::quote;

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyEncodingIn { Ascii, BinaryLittleEndian, BinaryBigEndian };

std::optional<PlyType> parse_type(std::string_view name) {
    if (name == "char" || name == "int8") return PlyType::Int8;
    if (name == "uchar" || name == "uint8") return PlyType::UInt8;
    if (name == "short" || name == "int16") return PlyType::Int16;
    if (name == "ushort" || name == "uint16") return PlyType::UInt16;
    if (name == "int" || name == "int32") return PlyType::Int32;
    if (name == "uint" || name == "uint32") return PlyType::UInt32;
    if (name == "float" || name == "float32") return PlyType::Float32;
    if (name == "double" || name == "float64") return PlyType::Float64;
    return std::nullopt;
}

std::size_t type_size(PlyType type) {
    switch (type) {
        case PlyType::Int8: case PlyType::UInt8: return 1;
        case PlyType::Int16: case PlyType::UInt16: return 2;
        case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
    }
    return 1;
}

bool is_integer(PlyType type) { return type != PlyType::Float32 && type != PlyType::Float64; }

struct PlyProperty {
    std::string_view name;
    PlyType type = PlyType::Float32;  //!< the value type, or the item type of a list
    bool is_list = false;
    PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
    std::string_view name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
    std::int64_t line = 0;  //!< header line that declares it

    //! Fewest bytes one item can take in a binary body (lists counted as empty).
    std::uint64_t min_binary_size() const {
        std::uint64_t size = 0;
        for (const auto& p : properties) size += p.is_list ? type_size(p.count_type) : type_size(p.type);
        return size;
    }
    int find(std::string_view property) const {
        for (std::size_t i = 0; i < properties.size(); ++i)
            if (properties[i].name == property) return static_cast<int>(i);
        return -1;
    }
};

struct PlyHeader {
    PlyEncodingIn encoding = PlyEncodingIn::Ascii;
    std::vector<PlyElement> elements;
    std::size_t body_offset = 0;
    std::int64_t body_line = 0;  //!< first line of an ascii body
};

// Values are assembled byte by byte in the file's order, which works the same on any host.
std::uint64_t load_bits(const unsigned char* p, std::size_t size, bool big_endian) {
    std::uint64_t bits = 0;
    if (big_endian) {
        for (std::size_t i = 0; i < size; ++i) bits = (bits << 8) | p[i];
    } else {
        for (std::size_t i = size; i-- > 0;) bits = (bits << 8) | p[i];
    }
    return bits;
}

double bits_to_double(std::uint64_t bits, PlyType type) {
    switch (type) {
        case PlyType::Int8: return static_cast<std::int8_t>(bits);
        case PlyType::UInt8: return static_cast<std::uint8_t>(bits);
        case PlyType::Int16: return static_cast<std::int16_t>(bits);
        case PlyType::UInt16: return static_cast<std::uint16_t>(bits);
        case PlyType::Int32: return static_cast<std::int32_t>(bits);
        case PlyType::UInt32: return static_cast<std::uint32_t>(bits);
        case PlyType::Float32: return std::bit_cast<float>(static_cast<std::uint32_t>(bits));
        case PlyType::Float64: return std::bit_cast<double>(bits);
    }
    return 0;
}

//! Integer types only (the header parser rejects float list counts and indices).
std::int64_t bits_to_int(std::uint64_t bits, PlyType type) {
    switch (type) {
        case PlyType::Int8: return static_cast<std::int8_t>(bits);
        case PlyType::UInt8: return static_cast<std::uint8_t>(bits);
        case PlyType::Int16: return static_cast<std::int16_t>(bits);
        case PlyType::UInt16: return static_cast<std::uint16_t>(bits);
        case PlyType::Int32: return static_cast<std::int32_t>(bits);
        case PlyType::UInt32: return static_cast<std::uint32_t>(bits);
        default: return 0;
    }
}

Result<PlyHeader> parse_header(std::string_view bytes, const ReadOptions& options) {
    if (bytes.empty()) return make_error(ErrorCode::ParseError, "empty file", -1, 0);
    if (bytes.size() >= 2 && ((static_cast<unsigned char>(bytes[0]) == 0xff && static_cast<unsigned char>(bytes[1]) == 0xfe) ||
                              (static_cast<unsigned char>(bytes[0]) == 0xfe && static_cast<unsigned char>(bytes[1]) == 0xff)))
        return make_error(ErrorCode::ParseError,
                          "UTF-16 is not supported (byte order mark at offset 0): save the file as UTF-8 or ASCII", -1, 0);
    std::size_t start = 0;
    if (bytes.size() >= 3 && bytes.substr(0, 3) == "\xef\xbb\xbf") start = 3;
    if (bytes.size() >= start + 2 && (bytes[start] == 0 || bytes[start + 1] == 0))
        return make_error(ErrorCode::ParseError, "UTF-16 is not supported (NUL byte in the header): save the file as UTF-8",
                          1, static_cast<std::int64_t>(start));

    io_detail::LineReader lines(bytes, start);
    std::string_view line;
    if (!lines.next(line) || line != "ply")
        return error_at_line(ErrorCode::ParseError, 1, "not a PLY file (the first line must be 'ply')");

    PlyHeader header;
    bool have_format = false;
    while (true) {
        if (!lines.next(line))
            return error_at_line(ErrorCode::ParseError, lines.line_number(), "header has no end_header line");
        const std::int64_t at = lines.line_number();
        if (line.find('\0') != std::string_view::npos)
            return error_at_line(ErrorCode::ParseError, at, "NUL byte in the header");
        io_detail::Tokens tokens(line);
        std::string_view keyword;
        if (!tokens.next(keyword)) continue;
        if (keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "end_header") break;
        if (keyword == "format") {
            std::string_view name, version;
            if (!tokens.next(name) || !tokens.next(version))
                return error_at_line(ErrorCode::ParseError, at, "format line needs an encoding and a version");
            if (name == "ascii") header.encoding = PlyEncodingIn::Ascii;
            else if (name == "binary_little_endian") header.encoding = PlyEncodingIn::BinaryLittleEndian;
            else if (name == "binary_big_endian") header.encoding = PlyEncodingIn::BinaryBigEndian;
            else return error_at_line(ErrorCode::ParseError, at, "unknown PLY format " + quote(name));
            if (!version.starts_with("1"))
                return error_at_line(ErrorCode::Unsupported, at, "PLY version " + quote(version) + " is not supported");
            have_format = true;
        } else if (keyword == "element") {
            PlyElement element;
            std::string_view count;
            std::int64_t n = 0;
            if (!tokens.next(element.name) || !tokens.next(count))
                return error_at_line(ErrorCode::ParseError, at, "element line needs a name and a count");
            if (io_detail::parse_int(count, n) != NumberStatus::Ok || n < 0)
                return error_at_line(ErrorCode::ParseError, at,
                                     "element count " + quote(count) + " is not a non-negative integer");
            element.count = static_cast<std::uint64_t>(n);
            element.line = at;
            for (const auto& other : header.elements)
                if (other.name == element.name)
                    return error_at_line(ErrorCode::ParseError, at, "element " + quote(element.name) + " declared twice");
            header.elements.push_back(element);
        } else if (keyword == "property") {
            if (header.elements.empty())
                return error_at_line(ErrorCode::ParseError, at, "property before any element");
            PlyProperty property;
            std::string_view type;
            if (!tokens.next(type)) return error_at_line(ErrorCode::ParseError, at, "property line has no type");
            if (type == "list") {
                std::string_view count_type, item_type;
                if (!tokens.next(count_type) || !tokens.next(item_type) || !tokens.next(property.name))
                    return error_at_line(ErrorCode::ParseError, at, "list property needs a count type, an item type and a name");
                auto ct = parse_type(count_type);
                auto it = parse_type(item_type);
                if (!ct) return error_at_line(ErrorCode::ParseError, at, "unknown property type " + quote(count_type));
                if (!it) return error_at_line(ErrorCode::ParseError, at, "unknown property type " + quote(item_type));
                if (!is_integer(*ct))
                    return error_at_line(ErrorCode::ParseError, at, "list count type " + quote(count_type) + " is not an integer type");
                property.is_list = true;
                property.count_type = *ct;
                property.type = *it;
            } else {
                auto t = parse_type(type);
                if (!t) return error_at_line(ErrorCode::ParseError, at, "unknown property type " + quote(type));
                if (!tokens.next(property.name)) return error_at_line(ErrorCode::ParseError, at, "property has no name");
                property.type = *t;
            }
            header.elements.back().properties.push_back(property);
        } else {
            return error_at_line(ErrorCode::ParseError, at, "unexpected " + quote(keyword) + " in the PLY header");
        }
    }
    if (!have_format) return error_at_line(ErrorCode::ParseError, lines.line_number(), "header has no format line");
    header.body_offset = lines.position();
    header.body_line = lines.line_number() + 1;

    // Check each element against the limits and the bytes that follow the header, before anything is reserved.
    const std::uint64_t remaining = bytes.size() - header.body_offset;
    std::uint64_t needed = 0;
    for (const PlyElement& e : header.elements) {
        // ascii: every value is at least one character and a separator
        const std::uint64_t item = header.encoding == PlyEncodingIn::Ascii ? 2 * e.properties.size() : e.min_binary_size();
        if (item == 0) continue;  // no properties: nothing to read
        const std::uint64_t left = remaining + 1 > needed ? remaining + 1 - needed : 0;  // +1: no final newline
        if (e.count > left / item) {
            GeoError error = error_at_line(ErrorCode::ParseError, e.line,
                                           "header declares " + std::to_string(e.count) + " " + quote(e.name) +
                                               " elements (at least " + std::to_string(item) + " bytes each) but only " +
                                               std::to_string(remaining) + " bytes follow the header");
            error.offset = static_cast<std::int64_t>(header.body_offset);
            return error;
        }
        needed += e.count * item;
    }
    for (const PlyElement& e : header.elements) {
        if (e.name == "vertex" && e.count > options.max_vertices)
            return error_at_line(ErrorCode::BudgetExceeded, e.line,
                                 "header declares " + std::to_string(e.count) + " vertices, more than max_vertices (" +
                                     std::to_string(options.max_vertices) + ")");
        if (e.name == "face" && e.count > options.max_faces)
            return error_at_line(ErrorCode::BudgetExceeded, e.line,
                                 "header declares " + std::to_string(e.count) + " faces, more than max_faces (" +
                                     std::to_string(options.max_faces) + ")");
    }
    return header;
}

//! Where the vertex and face data we keep sit among each element's properties.
struct Layout {
    int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1;
    int indices = -1;
};

class PlyReader {
public:
    PlyReader(std::string_view bytes, const ReadOptions& options) : bytes_(bytes), options_(options) {}

    Result<PolygonMesh> read() {
        auto parsed = parse_header(bytes_, options_);
        if (!parsed) return parsed.error();
        header_ = std::move(*parsed);

        const PlyElement* vertex = nullptr;
        const PlyElement* face = nullptr;
        for (const auto& e : header_.elements) {
            if (e.name == "vertex") vertex = &e;
            if (e.name == "face") face = &e;
        }
        if (!vertex) return error_at_line(ErrorCode::ParseError, header_.body_line - 1, "no vertex element in the header");
        if (!face || face->count == 0) return error_at_line(ErrorCode::ParseError, header_.body_line - 1, "no faces");
        layout_.x = vertex->find("x");
        layout_.y = vertex->find("y");
        layout_.z = vertex->find("z");
        for (const char* name : {"x", "y", "z"}) {
            const int i = vertex->find(name);
            if (i < 0)
                return error_at_line(ErrorCode::ParseError, vertex->line, std::string("vertex element has no '") + name + "' property");
            if (vertex->properties[static_cast<std::size_t>(i)].is_list)
                return error_at_line(ErrorCode::ParseError, vertex->line, std::string("vertex property '") + name + "' is a list");
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
    bool take(std::size_t n, const unsigned char*& p) {
        if (bytes_.size() - pos_ < n) return false;
        p = reinterpret_cast<const unsigned char*>(bytes_.data()) + pos_;
        pos_ += n;
        return true;
    }
    GeoError truncated(const PlyElement& e, std::uint64_t item) const {
        return error_at_offset(ErrorCode::ParseError, static_cast<std::int64_t>(pos_),
                               "unexpected end of file in " + quote(e.name) + " element " + std::to_string(item) + " of " +
                                   std::to_string(e.count));
    }

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
                    if (ki == layout_.x) p.x = value;
                    else if (ki == layout_.y) p.y = value;
                    else if (ki == layout_.z) p.z = value;
                    else if (ki == layout_.nx) n.x = value;
                    else if (ki == layout_.ny) n.y = value;
                    else if (ki == layout_.nz) n.z = value;
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
                    const std::int64_t v = bits_to_int(load_bits(bytes + i * item_size, item_size, big_endian_), prop.type);
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
                if (auto error = add_face(face, scratch, item, static_cast<std::int64_t>(item_offset), -1)) return error;
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
                                         "unexpected end of file in " + quote(e.name) + " element " + std::to_string(item) +
                                             " of " + std::to_string(e.count));
                if (item_line < 0) item_line = tokens.line();
                return std::nullopt;
            };
            for (std::size_t k = 0; k < e.properties.size(); ++k) {
                const PlyProperty& prop = e.properties[k];
                const int ki = static_cast<int>(k);
                if (auto error = next(token)) return error;
                if (!prop.is_list) {
                    if (r != Role::Vertex) continue;
                    double* target = ki == layout_.x ? &p.x : ki == layout_.y ? &p.y : ki == layout_.z ? &p.z
                                   : ki == layout_.nx ? &n.x : ki == layout_.ny ? &n.y : ki == layout_.nz ? &n.z : nullptr;
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
                        return error_at_line(ErrorCode::ParseError, tokens.line(), "face index " + quote(token) + " is not an integer");
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

    std::optional<GeoError> check_face_size(std::int64_t count, std::uint64_t item, std::int64_t offset, std::int64_t line) {
        if (static_cast<std::uint64_t>(count) > options_.max_face_size)
            return located(ErrorCode::BudgetExceeded, offset, line,
                           "face " + std::to_string(item) + " has " + std::to_string(count) +
                               " vertices, more than max_face_size (" + std::to_string(options_.max_face_size) + ")");
        if (count < 3)
            return located(ErrorCode::DegenerateFace, offset, line,
                           "face " + std::to_string(item) + " has " + std::to_string(count) +
                               " vertices (at least 3 needed)");
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
                return located(ErrorCode::DegenerateFace, offset, line,
                               "face " + std::to_string(item) + " uses vertex " + std::to_string(*dup) + " more than once");
        }
        if (mesh_.face_indices.size() + face.size() > io_detail::kMaxIndexCount)
            return located(ErrorCode::BudgetExceeded, offset, line, "more than 2^32 face corners");
        mesh_.add_face(face);
        return std::nullopt;
    }

    std::string_view bytes_;
    const ReadOptions& options_;
    PlyHeader header_;
    Layout layout_;
    bool read_normals_ = false;
    bool normals_finite_ = true;
    bool big_endian_ = false;
    std::size_t pos_ = 0;
    std::uint64_t vertex_count_ = 0;
    PolygonMesh mesh_;
};

void store_le(std::string& out, std::uint64_t bits, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) out += static_cast<char>((bits >> (8 * i)) & 0xff);
}

}  // namespace

Result<PolygonMesh> read_ply(std::string_view bytes, const ReadOptions& options) {
    return PlyReader(bytes, options).read();
}

std::string write_ply(const PolygonMesh& mesh, PlyEncoding encoding) {
    using io_detail::append_uint;
    const bool binary = encoding == PlyEncoding::BinaryLittleEndian;
    const bool normals = mesh.has_normals() && mesh.normals.size() == mesh.positions.size();
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
