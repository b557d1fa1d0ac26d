// Point-cloud readers (PLY, OBJ, XYZ) and the PLY writer. The PLY header and binary decoding are shared with the
// mesh reader (ply_header.h); tokenizing, numbers and error locations with every text reader (text_scanner.h).
#include "geometry/io/pointcloud_io.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/io/format_common.h"
#include "geometry/io/ply_header.h"
#include "geometry/io/text_encoding.h"
#include "geometry/io/text_scanner.h"

namespace surfaced {
namespace {

using io_detail::error_at_line;
using io_detail::error_at_offset;
using io_detail::NumberStatus;
using io_detail::quote;
using namespace io_detail::ply;

GeoError located(ErrorCode code, std::int64_t offset, std::int64_t line, const std::string& what) {
    return line >= 0 ? error_at_line(code, line, what) : error_at_offset(code, offset, what);
}

GeoError too_many_points(std::size_t limit, std::int64_t line) {
    return error_at_line(ErrorCode::BudgetExceeded, line,
                         "more than max_points (" + std::to_string(limit) + ") points");
}

//! Newline count + 1, capped: a reserve() size the bytes themselves justify.
std::size_t line_estimate(std::string_view text, std::size_t limit) {
    std::size_t lines = 1;
    for (const char* p = text.data();
         (p = static_cast<const char*>(
              std::memchr(p, '\n', static_cast<std::size_t>(text.data() + text.size() - p)))) != nullptr;
         ++p)
        ++lines;
    return io_detail::bounded_reserve(lines, limit);
}

// ---- PLY ----------------------------------------------------------------------------------------------------------

enum class Role : std::uint8_t { None, X, Y, Z, NX, NY, NZ, R, G, B, A, Confidence };

//! 1 / the largest value of an integer colour type (uchar 255 -> 1.0), 1 for float types.
double color_scale(PlyType type) {
    switch (type) {
        case PlyType::Int8: return 1.0 / 127.0;
        case PlyType::UInt8: return 1.0 / 255.0;
        case PlyType::Int16: return 1.0 / 32767.0;
        case PlyType::UInt16: return 1.0 / 65535.0;
        case PlyType::Int32: return 1.0 / 2147483647.0;
        case PlyType::UInt32: return 1.0 / 4294967295.0;
        default: return 1.0;
    }
}

class PlyPointReader : io_detail::ply::BinaryCursor {
public:
    PlyPointReader(std::string_view bytes, io_detail::TextEncoding encoding, const PointReadOptions& options)
        : BinaryCursor(bytes), encoding_(encoding), options_(options) {}

    Result<PointCloud> read() {
        ReadOptions limits;
        limits.max_vertices = options_.max_points;
        limits.max_faces = std::numeric_limits<std::size_t>::max();  // faces are skipped, bounded by the bytes
        auto parsed = parse_header(bytes_, limits, encoding_);
        if (!parsed) return parsed.error();
        header_ = std::move(*parsed);

        const PlyElement* vertex = nullptr;
        for (const auto& e : header_.elements)
            if (e.name == "vertex") vertex = &e;
        if (!vertex)
            return error_at_line(ErrorCode::ParseError, header_.body_line - 1, "no vertex element in the header");
        if (vertex->count == 0)
            return error_at_line(ErrorCode::ParseError, vertex->line, "the vertex element is empty");
        if (auto error = assign_roles(*vertex)) return std::move(*error);

        cloud_.positions.reserve(vertex->count);  // parse_header bounded it by the bytes present and max_points
        if (normals_) cloud_.normals.reserve(vertex->count);
        if (colors_) cloud_.colors.reserve(vertex->count);
        if (confidence_) cloud_.confidence.reserve(vertex->count);

        const bool ascii = header_.encoding == PlyEncodingIn::Ascii;
        io_detail::TokenReader tokens(bytes_, header_.body_offset, '\0', header_.body_line);
        pos_ = header_.body_offset;
        big_endian_ = header_.encoding == PlyEncodingIn::BinaryBigEndian;
        for (const auto& e : header_.elements) {
            const bool is_vertex = &e == vertex;
            if (auto error = ascii ? read_ascii_element(e, is_vertex, tokens) : read_binary_element(e, is_vertex))
                return std::move(*error);
            if (is_vertex) break;  // what follows (faces, edges) is not needed
        }
        if (!normals_finite_) cloud_.normals.clear();
        cloud_.has_alpha = colors_ && alpha_;
        return std::move(cloud_);
    }

private:
    std::optional<GeoError> assign_roles(const PlyElement& vertex) {
        roles_.assign(vertex.properties.size(), Role::None);
        auto find_scalar = [&](std::string_view name) {
            const int i = vertex.find(name);
            return i >= 0 && !vertex.properties[static_cast<std::size_t>(i)].is_list ? i : -1;
        };
        const char* names[] = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "alpha"};
        std::array<int, 10> at{};
        for (std::size_t i = 0; i < 10; ++i) at[i] = find_scalar(names[i]);
        for (std::size_t i = 0; i < 3; ++i)
            if (at[i] < 0)
                return error_at_line(ErrorCode::ParseError, vertex.line,
                                     std::string("vertex element has no scalar '") + names[i] + "' property");
        normals_ = at[3] >= 0 && at[4] >= 0 && at[5] >= 0;
        colors_ = at[6] >= 0 && at[7] >= 0 && at[8] >= 0;
        alpha_ = colors_ && at[9] >= 0;
        const std::size_t used = 3 + (normals_ ? 3 : 0) + (colors_ ? (alpha_ ? 4 : 3) : 0);
        for (std::size_t i = 0; i < used; ++i) {
            const std::size_t slot = i < 3 ? i : (normals_ ? i : i + 3);
            roles_[static_cast<std::size_t>(at[slot])] = static_cast<Role>(slot + 1);
        }
        // per-point confidence, under either name scanners use (PoissonRecon reads "confidence"; many write "quality")
        int confidence = find_scalar("confidence");
        if (confidence < 0) confidence = find_scalar("quality");
        confidence_ = confidence >= 0;
        if (confidence_) roles_[static_cast<std::size_t>(confidence)] = Role::Confidence;
        for (std::size_t k = 0; k < vertex.properties.size(); ++k) {
            const bool color = roles_[k] >= Role::R && roles_[k] <= Role::A;
            scales_.push_back(color ? color_scale(vertex.properties[k].type) : 1.0);
        }
        return std::nullopt;
    }

    //! values[role] for one vertex; colour channels already scaled to 0..1.
    using Values = std::array<double, 12>;

    std::optional<GeoError> add_point(const Values& v, std::uint64_t item, std::int64_t offset, std::int64_t line) {
        const Vec3 p{v[1], v[2], v[3]};
        if (!is_finite(p))
            return located(ErrorCode::NonFinite, offset, line,
                           "vertex " + std::to_string(item) + " has a non-finite coordinate");
        cloud_.positions.push_back(p);
        if (normals_) {
            const Vec3 n{v[4], v[5], v[6]};
            normals_finite_ = normals_finite_ && is_finite(n);
            const double len = norm(n);
            cloud_.normals.push_back(len > 0 && std::isfinite(len) ? n * (1.0 / len) : n);
        }
        if (colors_) {
            Color c{static_cast<float>(v[7]), static_cast<float>(v[8]), static_cast<float>(v[9]),
                    alpha_ ? static_cast<float>(v[10]) : 1.0f};
            for (float ch : {c.r, c.g, c.b, c.a})
                if (!(ch >= 0.0f && ch <= 1.0f))
                    return located(ErrorCode::ParseError, offset, line,
                                   "vertex " + std::to_string(item) +
                                       " has a colour channel outside 0..1 (float "
                                       "colours must be 0..1, integer ones are scaled by their type's maximum)");
            cloud_.colors.push_back(c);
        }
        if (confidence_) {
            const double w = v[11];
            if (!(w >= 0 && w <= std::numeric_limits<float>::max()))
                return located(ErrorCode::ParseError, offset, line,
                               "vertex " + std::to_string(item) + " has a confidence that is negative or not finite");
            cloud_.confidence.push_back(static_cast<float>(w));
        }
        return std::nullopt;
    }

    // ---- ascii
    std::optional<GeoError> read_ascii_element(const PlyElement& e, bool is_vertex, io_detail::TokenReader& tokens) {
        std::string_view token;
        for (std::uint64_t item = 0; item < e.count; ++item) {
            Values values{};
            std::int64_t item_line = -1;
            auto next = [&]() -> std::optional<GeoError> {
                if (!tokens.next(token))
                    return error_at_line(ErrorCode::ParseError, tokens.line(),
                                         "unexpected end of file in " + quote(e.name) + " element " +
                                             std::to_string(item) + " of " + std::to_string(e.count));
                if (item_line < 0) item_line = tokens.line();
                return std::nullopt;
            };
            for (std::size_t k = 0; k < e.properties.size(); ++k) {
                if (auto error = next()) return error;
                const PlyProperty& prop = e.properties[k];
                if (prop.is_list) {
                    std::int64_t count = 0;
                    if (io_detail::parse_int(token, count) != NumberStatus::Ok || count < 0)
                        return error_at_line(ErrorCode::ParseError, tokens.line(),
                                             "list length " + quote(token) + " is not a non-negative integer");
                    for (std::int64_t i = 0; i < count; ++i)  // one by one: a huge length runs into the end of file
                        if (auto error = next()) return error;
                    continue;
                }
                if (!is_vertex || roles_[k] == Role::None) continue;
                double value = 0;
                if (io_detail::parse_double(token, value) != NumberStatus::Ok)
                    return error_at_line(ErrorCode::ParseError, tokens.line(),
                                         "vertex value " + quote(token) + " is not a number");
                values[static_cast<std::size_t>(roles_[k])] = value * scales_[k];
            }
            if (is_vertex)
                if (auto error = add_point(values, item, -1, item_line)) return error;
        }
        return std::nullopt;
    }

    // ---- binary
    std::optional<GeoError> read_binary_element(const PlyElement& e, bool is_vertex) {
        for (std::uint64_t item = 0; item < e.count; ++item) {
            const std::size_t item_offset = pos_;
            Values values{};
            for (std::size_t k = 0; k < e.properties.size(); ++k) {
                const PlyProperty& prop = e.properties[k];
                const unsigned char* p = nullptr;
                if (prop.is_list) {
                    const std::size_t count_size = type_size(prop.count_type);
                    if (!take(count_size, p)) return truncated(e, item);
                    const std::int64_t count = bits_to_int(load_bits(p, count_size, big_endian_), prop.count_type);
                    if (count < 0)
                        return error_at_offset(ErrorCode::ParseError, static_cast<std::int64_t>(pos_ - count_size),
                                               "negative list length " + std::to_string(count));
                    const std::size_t item_size = type_size(prop.type);
                    if (static_cast<std::uint64_t>(count) > (bytes_.size() - pos_) / item_size)
                        return truncated(e, item);
                    pos_ += static_cast<std::size_t>(count) * item_size;
                    continue;
                }
                const std::size_t size = type_size(prop.type);
                if (!take(size, p)) return truncated(e, item);
                if (!is_vertex || roles_[k] == Role::None) continue;
                values[static_cast<std::size_t>(roles_[k])] =
                    bits_to_double(load_bits(p, size, big_endian_), prop.type) * scales_[k];
            }
            if (is_vertex)
                if (auto error = add_point(values, item, static_cast<std::int64_t>(item_offset), -1)) return error;
        }
        return std::nullopt;
    }

    io_detail::TextEncoding encoding_;
    const PointReadOptions& options_;
    PlyHeader header_;
    std::vector<Role> roles_;
    std::vector<double> scales_;
    bool normals_ = false, colors_ = false, alpha_ = false, confidence_ = false, normals_finite_ = true,
         big_endian_ = false;
    PointCloud cloud_;
};

// ---- text formats -------------------------------------------------------------------------------------------------

//! Colours read as numbers: 0..1, or 0..255 when any channel exceeds 1 (decided for the whole file).
std::optional<GeoError> check_color_value(double value, std::int64_t line) {
    if (!(value >= 0 && value <= 255))
        return error_at_line(ErrorCode::ParseError, line,
                             "colour value " + std::to_string(value) + " is outside 0..1 (or 0..255)");
    return std::nullopt;
}

void normalise_colors(std::vector<Color>& colors) {
    float largest = 0;
    for (const Color& c : colors) largest = std::max({largest, c.r, c.g, c.b});
    if (largest <= 1.0f) return;
    for (Color& c : colors) {
        c.r /= 255.0f;
        c.g /= 255.0f;
        c.b /= 255.0f;
    }
}

std::string_view strip_comment(std::string_view line) {
    if (const void* hash = std::memchr(line.data(), '#', line.size()))
        line = line.substr(0, static_cast<std::size_t>(static_cast<const char*>(hash) - line.data()));
    return line;
}

GeoError bad_number(std::int64_t line, std::string_view token, NumberStatus status) {
    return error_at_line(
        ErrorCode::ParseError, line,
        std::string(status == NumberStatus::OutOfRange ? "value is out of range: " : "value is not a number: ") +
            quote(token));
}

Vec3 unit_or_zero(const Vec3& n) {
    const double len = norm(n);
    return len > 0 && std::isfinite(len) ? n * (1.0 / len) : Vec3{};
}

//! read_obj_points on text that with_text has decoded.
Result<PointCloud> obj_points(std::string_view text, const PointReadOptions& options) {
    auto start = io_detail::check_text_encoding(text);
    if (!start) return start.error();
    PointCloud cloud;
    cloud.positions.reserve(line_estimate(text.substr(*start), options.max_points));
    std::vector<Vec3> normals;
    bool all_colored = true;
    io_detail::LineReader lines(text, *start, /*continuations=*/true);
    std::string_view line;
    while (lines.next(line)) {
        const std::int64_t at = lines.line_number();
        io_detail::Tokens tokens(strip_comment(line));
        std::string_view keyword, token;
        if (!tokens.next(keyword)) continue;
        if (keyword != "v" && keyword != "vn") continue;  // faces, groups, materials: not points
        std::array<double, 8> values{};
        std::size_t n = 0;
        while (tokens.next(token)) {
            if (n == values.size())
                return error_at_line(ErrorCode::ParseError, at, std::string(keyword) + " line has more than 7 values");
            if (auto status = io_detail::parse_double(token, values[n]); status != NumberStatus::Ok)
                return bad_number(at, token, status);
            ++n;
        }
        if (keyword == "vn") {
            if (n != 3)
                return error_at_line(ErrorCode::ParseError, at,
                                     "vn line has " + std::to_string(n) + " values (3 needed)");
            if (normals.size() >= options.max_points) return too_many_points(options.max_points, at);
            normals.push_back({values[0], values[1], values[2]});
            continue;
        }
        if (n < 3 || n == 5)
            return error_at_line(ErrorCode::ParseError, at,
                                 "v line has " + std::to_string(n) + " values (x y z, x y z w or x y z r g b)");
        const Vec3 p{values[0], values[1], values[2]};
        if (!is_finite(p))
            return error_at_line(ErrorCode::NonFinite, at,
                                 "vertex " + std::to_string(cloud.size() + 1) + " has a non-finite coordinate");
        if (cloud.size() >= options.max_points) return too_many_points(options.max_points, at);
        cloud.positions.push_back(p);
        if (n >= 6 && all_colored) {
            for (std::size_t i = 3; i < 6; ++i)
                if (auto error = check_color_value(values[i], at)) return std::move(*error);
            cloud.colors.push_back(
                {static_cast<float>(values[3]), static_cast<float>(values[4]), static_cast<float>(values[5]), 1.0f});
        } else {
            all_colored = false;
        }
    }
    if (cloud.empty()) return make_error(ErrorCode::ParseError, "no points (no 'v' lines)");
    if (!all_colored) cloud.colors.clear();
    normalise_colors(cloud.colors);
    bool normals_finite = true;
    for (const Vec3& n : normals) normals_finite = normals_finite && is_finite(n);
    if (normals.size() == cloud.size() && normals_finite) {
        for (Vec3& n : normals) n = unit_or_zero(n);
        cloud.normals = std::move(normals);
    }
    return cloud;
}

//! read_xyz_points on text that with_text has decoded.
Result<PointCloud> xyz_points(std::string_view text, const PointReadOptions& options) {
    auto start = io_detail::check_text_encoding(text);
    if (!start) return start.error();
    PointCloud cloud;
    const std::size_t estimate = line_estimate(text.substr(*start), options.max_points);
    cloud.positions.reserve(estimate);
    std::size_t columns = 0;
    std::int64_t first_line = 0;
    io_detail::LineReader lines(text, *start);
    std::string_view line;
    std::array<double, 9> values{};
    while (lines.next(line)) {
        const std::int64_t at = lines.line_number();
        line = strip_comment(line);
        std::size_t n = 0;
        std::size_t i = 0;
        while (i < line.size()) {
            // values are separated by whitespace and/or one comma
            while (i < line.size() && (io_detail::is_space(line[i]) || line[i] == ',')) ++i;
            if (i == line.size()) break;
            std::size_t j = i;
            while (j < line.size() && !io_detail::is_space(line[j]) && line[j] != ',') ++j;
            const std::string_view token = line.substr(i, j - i);
            i = j;
            if (n == values.size())
                return error_at_line(ErrorCode::ParseError, at,
                                     "more than 9 values on one line (x y z [nx ny nz] [r g b])");
            if (auto status = io_detail::parse_double(token, values[n]); status != NumberStatus::Ok)
                return bad_number(at, token, status);
            ++n;
        }
        if (n == 0) continue;
        if (columns == 0) {
            if (n != 3 && n != 6 && n != 9)
                return error_at_line(ErrorCode::ParseError, at,
                                     "line has " + std::to_string(n) +
                                         " values; expected 3 (x y z), 6 (+ nx ny nz) or "
                                         "9 (+ r g b)");
            columns = n;
            first_line = at;
            if (columns >= 6) cloud.normals.reserve(estimate);
            if (columns == 9) cloud.colors.reserve(estimate);
        } else if (n != columns) {
            return error_at_line(ErrorCode::ParseError, at,
                                 "line has " + std::to_string(n) + " values, but the first point (line " +
                                     std::to_string(first_line) + ") has " + std::to_string(columns));
        }
        const Vec3 p{values[0], values[1], values[2]};
        if (!is_finite(p))
            return error_at_line(ErrorCode::NonFinite, at,
                                 "point " + std::to_string(cloud.size()) + " has a non-finite coordinate");
        if (cloud.size() >= options.max_points) return too_many_points(options.max_points, at);
        cloud.positions.push_back(p);
        if (columns >= 6) {
            const Vec3 nrm{values[3], values[4], values[5]};
            if (!is_finite(nrm))
                return error_at_line(ErrorCode::NonFinite, at,
                                     "normal of point " + std::to_string(cloud.size() - 1) + " is not finite");
            cloud.normals.push_back(unit_or_zero(nrm));
        }
        if (columns == 9) {
            for (std::size_t c = 6; c < 9; ++c)
                if (auto error = check_color_value(values[c], at)) return std::move(*error);
            cloud.colors.push_back(
                {static_cast<float>(values[6]), static_cast<float>(values[7]), static_cast<float>(values[8]), 1.0f});
        }
    }
    if (cloud.empty()) return make_error(ErrorCode::ParseError, "no points (only blank or comment lines)");
    normalise_colors(cloud.colors);
    return cloud;
}

}  // namespace

Result<PointCloud> read_ply_points(std::string_view bytes, const PointReadOptions& options) {
    return io_detail::with_text(bytes, [&](std::string_view text, io_detail::TextEncoding encoding) {
        return PlyPointReader(text, encoding, options).read();
    });
}

Result<PointCloud> read_obj_points(std::string_view text, const PointReadOptions& options) {
    return io_detail::with_text(
        text, [&](std::string_view decoded, io_detail::TextEncoding) { return obj_points(decoded, options); });
}

Result<PointCloud> read_xyz_points(std::string_view text, const PointReadOptions& options) {
    return io_detail::with_text(
        text, [&](std::string_view decoded, io_detail::TextEncoding) { return xyz_points(decoded, options); });
}

std::optional<PointFormat> point_format_from_extension(std::string_view path) {
    const std::size_t slash = path.find_last_of("/\\");
    if (slash != std::string_view::npos) path.remove_prefix(slash + 1);
    const std::size_t dot = path.rfind('.');
    if (dot == std::string_view::npos) return std::nullopt;
    const std::string_view ext = path.substr(dot + 1);
    if (io_detail::iequals(ext, "ply")) return PointFormat::Ply;
    if (io_detail::iequals(ext, "obj")) return PointFormat::Obj;
    if (io_detail::iequals(ext, "xyz") || io_detail::iequals(ext, "txt") || io_detail::iequals(ext, "pts"))
        return PointFormat::Xyz;
    if (io_detail::iequals(ext, "glb")) return PointFormat::Glb;
    if (io_detail::iequals(ext, "gltf")) return PointFormat::Gltf;
    return std::nullopt;
}

std::optional<PointFormat> point_format_from_media_type(std::string_view media_type) {
    if (auto mesh = format_from_media_type(media_type)) {
        if (*mesh == MeshFormat::Ply) return PointFormat::Ply;
        if (*mesh == MeshFormat::Obj) return PointFormat::Obj;
        if (*mesh == MeshFormat::Glb) return PointFormat::Glb;
        if (*mesh == MeshFormat::Gltf) return PointFormat::Gltf;
        return std::nullopt;
    }
    std::string_view type = media_type.substr(0, media_type.find(';'));
    while (!type.empty() && io_detail::is_space(type.back())) type.remove_suffix(1);
    while (!type.empty() && io_detail::is_space(type.front())) type.remove_prefix(1);
    for (std::string_view xyz : {"text/x-xyz", "chemical/x-xyz", "application/x-xyz", "model/x-xyz"})
        if (io_detail::iequals(type, xyz)) return PointFormat::Xyz;
    return std::nullopt;
}

std::string_view point_media_type(PointFormat format) {
    switch (format) {
        case PointFormat::Ply: return "application/ply";
        case PointFormat::Obj: return "model/obj";
        case PointFormat::Xyz: return "text/x-xyz";
        case PointFormat::Glb: return "model/gltf-binary";
        case PointFormat::Gltf: return "model/gltf+json";
    }
    return "application/octet-stream";
}

std::optional<PointFormat> sniff_point_format(std::string_view bytes) {
    if (const auto mesh = sniff_format(bytes); mesh == MeshFormat::Glb || mesh == MeshFormat::Gltf)
        return mesh == MeshFormat::Glb ? PointFormat::Glb : PointFormat::Gltf;
    std::string_view text = bytes;
    if (text.substr(0, 3) == "\xef\xbb\xbf") text.remove_prefix(3);
    if (text.substr(0, 4) == "ply\n" || text.substr(0, 5) == "ply\r\n") return PointFormat::Ply;
    io_detail::LineReader lines(text, 0);
    std::string_view line;
    for (int seen = 0; seen < 64 && lines.next(line);) {
        if (line.find('\0') != std::string_view::npos) return std::nullopt;
        io_detail::Tokens tokens(strip_comment(line));
        std::string_view word;
        if (!tokens.next(word)) continue;
        ++seen;
        if (word == "v" || word == "vn" || word == "f" || word == "o" || word == "g" || word == "mtllib")
            return PointFormat::Obj;
        double value = 0;
        if (word.back() == ',') word.remove_suffix(1);
        if (io_detail::parse_double(word, value) == NumberStatus::Ok) return PointFormat::Xyz;
        return std::nullopt;
    }
    return std::nullopt;
}

std::string write_ply_points(const PointCloud& cloud, PlyEncoding encoding) {
    using io_detail::append_uint;
    const bool binary = encoding == PlyEncoding::BinaryLittleEndian;
    const bool normals = cloud.has_normals() && cloud.normals.size() == cloud.size();
    const bool colors = cloud.has_colors() && cloud.colors.size() == cloud.size();
    const bool alpha = colors && cloud.has_alpha;
    const bool confidence = cloud.has_confidence() && cloud.confidence.size() == cloud.size();
    std::string out;
    out.reserve(256 + cloud.size() * ((normals ? 48 : 24) + (colors ? 4 : 0)) * (binary ? 1 : 2));
    out += "ply\nformat ";
    out += binary ? "binary_little_endian" : "ascii";
    out += " 1.0\ncomment written by surfaced\nelement vertex ";
    append_uint(out, cloud.size());
    out += "\nproperty double x\nproperty double y\nproperty double z\n";
    if (normals) out += "property double nx\nproperty double ny\nproperty double nz\n";
    if (colors) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    if (alpha) out += "property uchar alpha\n";
    if (confidence) out += "property float confidence\n";
    out += "end_header\n";
    auto channel = [](float v) { return static_cast<unsigned>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    for (std::size_t i = 0; i < cloud.size(); ++i) {
        const Vec3& p = cloud.positions[i];
        const Vec3 n = normals ? cloud.normals[i] : Vec3{};
        const double values[6] = {p.x, p.y, p.z, n.x, n.y, n.z};
        const int count = normals ? 6 : 3;
        for (int k = 0; k < count; ++k) {
            if (binary) {
                const auto bits = std::bit_cast<std::uint64_t>(values[k]);
                for (int b = 0; b < 8; ++b) out += static_cast<char>((bits >> (8 * b)) & 0xff);
            } else {
                if (k > 0) out += ' ';
                io_detail::append_double(out, values[k], 17);
            }
        }
        if (colors) {
            const Color& c = cloud.colors[i];
            const unsigned rgba[4] = {channel(c.r), channel(c.g), channel(c.b), channel(c.a)};
            for (int k = 0; k < (alpha ? 4 : 3); ++k) {
                if (binary) {
                    out += static_cast<char>(rgba[k]);
                } else {
                    out += ' ';
                    append_uint(out, rgba[k]);
                }
            }
        }
        if (confidence) {
            const float w = cloud.confidence[i];
            if (binary) {
                const auto bits = std::bit_cast<std::uint32_t>(w);
                for (int b = 0; b < 4; ++b) out += static_cast<char>((bits >> (8 * b)) & 0xff);
            } else {
                out += ' ';
                io_detail::append_double(out, static_cast<double>(w), 9);
            }
        }
        if (!binary) out += '\n';
    }
    return out;
}

}  // namespace surfaced
