// Wavefront OBJ reader and writer, including OpenSubdiv's `t` tag lines (regression/common/shape_utils.cpp).
#include <cstring>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/io/format_common.h"
#include "geometry/io/mesh_io.h"
#include "geometry/io/text_encoding.h"
#include "geometry/io/text_scanner.h"

namespace surfaced {
namespace {

using io_detail::error_at_line;
using io_detail::NumberStatus;
using io_detail::quote;
using io_detail::Tokens;

bool is_identifier(std::string_view s) {
    if (s.empty()) return false;
    auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
    if (!alpha(s[0])) return false;
    for (char c : s)
        if (!alpha(c) && !(c >= '0' && c <= '9')) return false;
    return true;
}

//! Lines that start with `prefix` (e.g. "v ") counted in one memchr pass: an exact size for reserve() that the
//! bytes themselves justify.
std::size_t count_lines_starting_with(std::string_view text, std::string_view prefix) {
    std::size_t count = 0, pos = 0;
    while (pos < text.size()) {
        if (text.compare(pos, prefix.size(), prefix) == 0) ++count;
        const void* nl = std::memchr(text.data() + pos, '\n', text.size() - pos);
        if (!nl) break;
        pos = static_cast<std::size_t>(static_cast<const char*>(nl) - text.data()) + 1;
    }
    return count;
}

class ObjReader {
public:
    ObjReader(std::string_view text, const ReadOptions& options, ReadReport* report)
        : text_(text), options_(options), report_(report) {}

    Result<PolygonMesh> read() {
        auto start = io_detail::check_text_encoding(text_);
        if (!start) return start.error();
        const std::string_view body = text_.substr(*start);
        mesh_.positions.reserve(
            io_detail::bounded_reserve(count_lines_starting_with(body, "v "), options_.max_vertices));
        const std::size_t face_estimate =
            io_detail::bounded_reserve(count_lines_starting_with(body, "f "), options_.max_faces);
        mesh_.face_offsets.reserve(face_estimate + 1);
        mesh_.face_indices.reserve(face_estimate * 4);

        io_detail::LineReader lines(text_, *start, /*continuations=*/true);
        std::string_view line;
        while (lines.next(line)) {
            line_ = lines.line_number();
            if (auto error = parse_line(line)) return std::move(*error);
        }
        return finish();
    }

private:
    std::optional<GeoError> parse_line(std::string_view line) {
        // '#' starts a comment anywhere on a line ("f 1 2 3 # note")
        if (const void* hash = std::memchr(line.data(), '#', line.size()))
            line = line.substr(0, static_cast<std::size_t>(static_cast<const char*>(hash) - line.data()));
        Tokens tokens(line);
        std::string_view keyword;
        if (!tokens.next(keyword)) return std::nullopt;  // blank or comment
        if (keyword == "v") return parse_vertex(tokens);
        if (keyword == "f") return parse_face(tokens);
        if (keyword == "vt") return parse_uv(tokens);
        if (keyword == "vn") {
            // Normals are not kept, but counted so that v//vn references can be range-checked.
            ++normal_count_;
            return std::nullopt;
        }
        if (keyword == "t") return parse_tag(tokens);
        // g, o, s, usemtl, mtllib, l, p, vp and the free-form statements carry nothing we keep. A keyword that is
        // not even a word is garbage, and saying so beats reporting "no faces" at the end.
        if (!is_identifier(keyword))
            return error_at_line(ErrorCode::ParseError, line_,
                                 "unexpected " + quote(keyword) + " (not an OBJ statement)");
        return std::nullopt;
    }

    std::optional<GeoError> bad_number(std::string_view what, std::string_view token, NumberStatus status) {
        return error_at_line(ErrorCode::ParseError, line_,
                             std::string(what) +
                                 (status == NumberStatus::OutOfRange ? " is out of range: " : " is not a number: ") +
                                 quote(token));
    }

    std::optional<GeoError> parse_vertex(Tokens& tokens) {
        Vec3 p;
        for (int i = 0; i < 3; ++i) {
            std::string_view token;
            if (!tokens.next(token))
                return error_at_line(ErrorCode::ParseError, line_,
                                     "vertex has " + std::to_string(i) + " coordinates (3 needed)");
            if (auto status = io_detail::parse_double(token, p[i]); status != NumberStatus::Ok)
                return bad_number("vertex coordinate", token, status);
        }
        // An optional w or vertex colours may follow; they are not kept.
        if (!is_finite(p))
            return error_at_line(
                ErrorCode::NonFinite, line_,
                "vertex " + std::to_string(mesh_.positions.size() + 1) + " has a non-finite coordinate");
        if (mesh_.positions.size() >= options_.max_vertices)
            return error_at_line(ErrorCode::BudgetExceeded, line_,
                                 "more than max_vertices (" + std::to_string(options_.max_vertices) + ") vertices");
        mesh_.positions.push_back(p);
        return std::nullopt;
    }

    std::optional<GeoError> parse_uv(Tokens& tokens) {
        Vec2 uv;
        std::string_view token;
        if (!tokens.next(token)) return error_at_line(ErrorCode::ParseError, line_, "texture coordinate has no values");
        if (auto status = io_detail::parse_double(token, uv.x); status != NumberStatus::Ok)
            return bad_number("texture coordinate", token, status);
        if (tokens.next(token)) {  // v is optional in OBJ (1D textures); it defaults to 0
            if (auto status = io_detail::parse_double(token, uv.y); status != NumberStatus::Ok)
                return bad_number("texture coordinate", token, status);
        }
        if (!is_finite(uv))
            return error_at_line(ErrorCode::NonFinite, line_,
                                 "texture coordinate " + std::to_string(mesh_.uvs.size() + 1) + " is not finite");
        if (mesh_.uvs.size() >= options_.max_vertices)
            return error_at_line(
                ErrorCode::BudgetExceeded, line_,
                "more than max_vertices (" + std::to_string(options_.max_vertices) + ") texture coordinates");
        mesh_.uvs.push_back(uv);
        return std::nullopt;
    }

    //! OBJ indices are 1-based, or negative to count back from the last element read so far.
    std::optional<GeoError> resolve(std::string_view token, std::size_t count, const char* what, const char* plural,
                                    Index& out) {
        std::int64_t raw = 0;
        if (auto status = io_detail::parse_int(token, raw); status != NumberStatus::Ok)
            return error_at_line(
                status == NumberStatus::OutOfRange ? ErrorCode::IndexOutOfRange : ErrorCode::ParseError, line_,
                std::string(what) + " index " + quote(token) +
                    (status == NumberStatus::OutOfRange ? " out of range" : " is not an integer"));
        if (raw == 0)
            return error_at_line(ErrorCode::IndexOutOfRange, line_,
                                 std::string(what) + " index 0 is invalid (OBJ indices start at 1)");
        const auto n = static_cast<std::int64_t>(count);
        const std::int64_t resolved = raw > 0 ? raw - 1 : n + raw;
        if (resolved < 0 || resolved >= n)
            return error_at_line(ErrorCode::IndexOutOfRange, line_,
                                 std::string(what) + " index " + std::to_string(raw) + " out of range (" +
                                     std::to_string(count) + " " + plural + ")");
        out = static_cast<Index>(resolved);
        return std::nullopt;
    }

    std::optional<GeoError> parse_face(Tokens& tokens) {
        face_.clear();
        face_uvs_.clear();
        std::size_t corners_with_uv = 0;
        std::string_view token;
        while (tokens.next(token)) {
            if (face_.size() >= options_.max_face_size)
                return error_at_line(
                    ErrorCode::BudgetExceeded, line_,
                    "face has more than max_face_size (" + std::to_string(options_.max_face_size) + ") vertices");
            // v, v/vt, v//vn or v/vt/vn
            const std::size_t slash1 = token.find('/');
            const std::string_view v_part = token.substr(0, slash1);
            Index v = 0;
            if (auto error = resolve(v_part, mesh_.positions.size(), "face", "vertices", v)) return error;
            face_.push_back(v);
            if (slash1 == std::string_view::npos) continue;
            const std::string_view after = token.substr(slash1 + 1);
            const std::size_t slash2 = after.find('/');
            const std::string_view vt_part = after.substr(0, slash2);
            if (!vt_part.empty()) {
                Index vt = 0;
                if (auto error = resolve(vt_part, mesh_.uvs.size(), "texture coordinate", "texture coordinates", vt))
                    return error;
                face_uvs_.push_back(vt);
                ++corners_with_uv;
            }
            if (slash2 != std::string_view::npos) {
                const std::string_view vn_part = after.substr(slash2 + 1);
                Index vn = 0;
                if (vn_part.empty() || vn_part.find('/') != std::string_view::npos)
                    return error_at_line(ErrorCode::ParseError, line_, "malformed face corner " + quote(token));
                if (auto error = resolve(vn_part, normal_count_, "normal", "normals", vn)) return error;
            }
        }
        if (face_.size() < 3)
            return error_at_line(ErrorCode::DegenerateFace, line_,
                                 "face has " + std::to_string(face_.size()) + " vertices (at least 3 needed)");
        if (corners_with_uv != 0 && corners_with_uv != face_.size())
            return error_at_line(ErrorCode::ParseError, line_,
                                 "face mixes corners with and without texture coordinates");
        if (!options_.allow_repeated_vertices) {
            if (auto dup = io_detail::repeated_vertex(face_, scratch_))
                return error_at_line(ErrorCode::DegenerateFace, line_,
                                     "face uses vertex " + std::to_string(*dup + 1) + " more than once");
        }
        if (mesh_.face_count() >= options_.max_faces)
            return error_at_line(ErrorCode::BudgetExceeded, line_,
                                 "more than max_faces (" + std::to_string(options_.max_faces) + ") faces");
        if (mesh_.face_indices.size() + face_.size() > io_detail::kMaxIndexCount)
            return error_at_line(ErrorCode::BudgetExceeded, line_, "more than 2^32 face corners");
        mesh_.add_face(face_);
        io_detail::record_face_line(report_, line_);
        if (corners_with_uv != 0) {
            ++faces_with_uv_;
            // Once a face without vt has been seen the uvs will be dropped; stop collecting them.
            if (faces_without_uv_ == 0)
                mesh_.uv_indices.insert(mesh_.uv_indices.end(), face_uvs_.begin(), face_uvs_.end());
        } else {
            ++faces_without_uv_;
        }
        return std::nullopt;
    }

    // t NAME nints/nfloats/nstrings ints... floats... strings...
    std::optional<GeoError> parse_tag(Tokens& tokens) {
        std::string_view name, counts, token;
        if (!tokens.next(name)) return error_at_line(ErrorCode::ParseError, line_, "tag has no name");
        if (!tokens.next(counts))
            return error_at_line(ErrorCode::ParseError, line_, "tag " + quote(name) + " has no argument counts");
        std::int64_t n[3] = {0, 0, 0};
        {
            std::string_view rest = counts;
            for (int i = 0; i < 3; ++i) {
                const std::size_t slash = i < 2 ? rest.find('/') : std::string_view::npos;
                if (i < 2 && slash == std::string_view::npos) {
                    return error_at_line(ErrorCode::ParseError, line_,
                                         "tag " + quote(name) + " has malformed argument counts " + quote(counts) +
                                             " (expected ints/floats/strings)");
                }
                const std::string_view part = rest.substr(0, slash);
                if (io_detail::parse_int(part, n[i]) != NumberStatus::Ok || n[i] < 0)
                    return error_at_line(ErrorCode::ParseError, line_,
                                         "tag " + quote(name) + " has malformed argument counts " + quote(counts) +
                                             " (expected ints/floats/strings)");
                if (i < 2) rest = rest.substr(slash + 1);
            }
        }
        // A count beyond what the line holds can never be satisfied; rejecting it here also keeps the sum below
        // from overflowing.
        const std::int64_t line_limit = static_cast<std::int64_t>(tokens.rest().size());
        if (n[0] > line_limit || n[1] > line_limit || n[2] > line_limit) {
            std::int64_t present = 0;
            for (Tokens rest = tokens; rest.next(token);) ++present;
            return error_at_line(ErrorCode::ParseError, line_,
                                 "tag " + quote(name) + " declares " + std::string(counts) +
                                     " arguments but has only " + std::to_string(present));
        }
        const bool known = name == "crease" || name == "corner" || name == "hole" || name == "interpolateboundary";
        tag_ints_.clear();
        tag_floats_.clear();
        // Counts are only compared with tokens actually present, never used to size anything.
        for (std::int64_t i = 0; i < n[0] + n[1] + n[2]; ++i) {
            if (!tokens.next(token))
                return error_at_line(ErrorCode::ParseError, line_,
                                     "tag " + quote(name) + " declares " + std::string(counts) +
                                         " arguments but has only " + std::to_string(i));
            if (!known || i >= n[0] + n[1]) continue;  // other tags and all strings: counted, not kept
            if (i < n[0]) {
                std::int64_t value = 0;
                if (auto status = io_detail::parse_int(token, value); status != NumberStatus::Ok)
                    return error_at_line(
                        ErrorCode::ParseError, line_,
                        "tag " + quote(name) + " integer argument " + quote(token) + " is not an integer");
                tag_ints_.push_back(value);
            } else {
                double value = 0;
                if (auto status = io_detail::parse_double(token, value); status != NumberStatus::Ok)
                    return error_at_line(ErrorCode::ParseError, line_,
                                         "tag " + quote(name) + " float argument " + quote(token) + " is not a number");
                tag_floats_.push_back(value);
            }
        }
        if (name == "crease") return apply_crease(counts);
        if (name == "corner") return apply_corner(counts);
        if (name == "hole") return apply_hole();
        if (name == "interpolateboundary") return apply_boundary(counts);
        return std::nullopt;
    }

    std::optional<GeoError> sharpness(std::size_t i, double& out) {
        out = tag_floats_.size() == 1 ? tag_floats_[0] : tag_floats_[i];
        if (!std::isfinite(out)) return error_at_line(ErrorCode::NonFinite, line_, "sharpness is not finite");
        if (out < 0) out = 0;  // OpenSubdiv clamps negative sharpness to 0 (smooth)
        return std::nullopt;
    }

    std::optional<GeoError> tag_index(std::int64_t value, const char* what, Index& out) {
        if (value < 0 || value > static_cast<std::int64_t>(kInvalidIndex) - 1)
            return error_at_line(ErrorCode::IndexOutOfRange, line_,
                                 std::string(what) + " index " + std::to_string(value) + " out of range");
        out = static_cast<Index>(value);
        return std::nullopt;
    }

    std::optional<GeoError> apply_crease(std::string_view counts) {
        const std::size_t pairs = tag_ints_.size() / 2;
        if (tag_ints_.size() < 2 || tag_ints_.size() % 2 != 0 ||
            (tag_floats_.size() != 1 && tag_floats_.size() != pairs))
            return error_at_line(
                ErrorCode::ParseError, line_,
                "crease tag needs vertex pairs and one sharpness (or one per pair), got " + std::string(counts));
        for (std::size_t i = 0; i < pairs; ++i) {
            Crease c;
            if (auto e = tag_index(tag_ints_[2 * i], "crease vertex", c.v0)) return e;
            if (auto e = tag_index(tag_ints_[2 * i + 1], "crease vertex", c.v1)) return e;
            if (c.v0 == c.v1)
                return error_at_line(ErrorCode::DegenerateFace, line_,
                                     "crease edge goes from vertex " + std::to_string(c.v0) + " to itself");
            if (auto e = sharpness(i, c.sharpness)) return e;
            mesh_.tags.creases.push_back(c);
            crease_lines_.push_back(line_);
        }
        return std::nullopt;
    }

    std::optional<GeoError> apply_corner(std::string_view counts) {
        if (tag_ints_.empty() || (tag_floats_.size() != 1 && tag_floats_.size() != tag_ints_.size()))
            return error_at_line(
                ErrorCode::ParseError, line_,
                "corner tag needs vertices and one sharpness (or one per vertex), got " + std::string(counts));
        for (std::size_t i = 0; i < tag_ints_.size(); ++i) {
            Corner c;
            if (auto e = tag_index(tag_ints_[i], "corner vertex", c.vertex)) return e;
            if (auto e = sharpness(i, c.sharpness)) return e;
            mesh_.tags.corners.push_back(c);
            corner_lines_.push_back(line_);
        }
        return std::nullopt;
    }

    std::optional<GeoError> apply_hole() {
        for (std::int64_t value : tag_ints_) {
            Index f = 0;
            if (auto e = tag_index(value, "hole face", f)) return e;
            mesh_.tags.holes.push_back(f);
            hole_lines_.push_back(line_);
        }
        return std::nullopt;
    }

    std::optional<GeoError> apply_boundary(std::string_view counts) {
        if (tag_ints_.size() != 1)
            return error_at_line(ErrorCode::ParseError, line_,
                                 "interpolateboundary tag needs one integer, got " + std::string(counts));
        switch (tag_ints_[0]) {  // Sdc::Options::VtxBoundaryInterpolation numbering
            case 0: mesh_.tags.boundary = BoundaryInterpolation::None; break;
            case 1: mesh_.tags.boundary = BoundaryInterpolation::EdgeAndCorner; break;
            case 2: mesh_.tags.boundary = BoundaryInterpolation::EdgeOnly; break;
            default:
                return error_at_line(ErrorCode::ParseError, line_,
                                     "interpolateboundary value " + std::to_string(tag_ints_[0]) + " is not 0, 1 or 2");
        }
        return std::nullopt;
    }

    //! Tags may come before the geometry they name, so their ranges are checked once everything is read.
    Result<PolygonMesh> finish() {
        if (mesh_.face_count() == 0) return make_error(ErrorCode::ParseError, "no faces");
        const std::size_t nv = mesh_.positions.size(), nf = mesh_.face_count();
        const auto& tags = mesh_.tags;
        for (std::size_t i = 0; i < tags.creases.size(); ++i) {
            const Index bad = tags.creases[i].v0 >= nv ? tags.creases[i].v0 : tags.creases[i].v1;
            if (bad >= nv)
                return error_at_line(ErrorCode::IndexOutOfRange, crease_lines_[i],
                                     "crease refers to vertex " + std::to_string(bad) + " but there are " +
                                         std::to_string(nv) + " vertices (tag indices are 0-based)");
        }
        for (std::size_t i = 0; i < tags.corners.size(); ++i)
            if (tags.corners[i].vertex >= nv)
                return error_at_line(ErrorCode::IndexOutOfRange, corner_lines_[i],
                                     "corner refers to vertex " + std::to_string(tags.corners[i].vertex) +
                                         " but there are " + std::to_string(nv) +
                                         " vertices (tag indices are 0-based)");
        for (std::size_t i = 0; i < tags.holes.size(); ++i)
            if (tags.holes[i] >= nf)
                return error_at_line(ErrorCode::IndexOutOfRange, hole_lines_[i],
                                     "hole refers to face " + std::to_string(tags.holes[i]) + " but there are " +
                                         std::to_string(nf) + " faces (tag indices are 0-based)");
        // Texture coordinates only when every face has them (see mesh_io.h).
        if (faces_without_uv_ != 0 || faces_with_uv_ == 0) {
            mesh_.uvs.clear();
            mesh_.uv_indices.clear();
        }
        return std::move(mesh_);
    }

    std::string_view text_;
    const ReadOptions& options_;
    ReadReport* report_;
    PolygonMesh mesh_;
    std::int64_t line_ = 0;
    std::size_t normal_count_ = 0;
    std::size_t faces_with_uv_ = 0, faces_without_uv_ = 0;
    std::vector<Index> face_, face_uvs_, scratch_;
    std::vector<std::int64_t> tag_ints_;
    std::vector<double> tag_floats_;
    std::vector<std::int64_t> crease_lines_, corner_lines_, hole_lines_;
};

void write_vec(std::string& out, const char* keyword, std::initializer_list<double> values, int precision) {
    out += keyword;
    for (double v : values) {
        out += ' ';
        io_detail::append_double(out, v, precision);
    }
    out += '\n';
}

}  // namespace

Result<PolygonMesh> read_obj(std::string_view text, const ReadOptions& options) {
    return read_obj(text, options, nullptr);
}

Result<PolygonMesh> read_obj(std::string_view text, const ReadOptions& options, ReadReport* report) {
    return io_detail::with_text(text, [&](std::string_view decoded, io_detail::TextEncoding) {
        return ObjReader(decoded, options, report).read();
    });
}

std::string write_obj(const PolygonMesh& mesh, const ObjWriteOptions& options) {
    using io_detail::append_uint;
    const int precision = options.precision;
    const bool uvs = options.write_uvs && mesh.has_uvs();
    const bool normals = options.write_normals && mesh.has_normals();
    std::string out;
    out.reserve(mesh.positions.size() * 64 + mesh.face_indices.size() * 12 + 64);
    out += "# surfaced: ";
    append_uint(out, mesh.vertex_count());
    out += " vertices, ";
    append_uint(out, mesh.face_count());
    out += " faces\n";
    const bool colors = options.vertex_colors.size() == mesh.positions.size() && !mesh.positions.empty();
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3& p = mesh.positions[v];
        if (colors) {
            const Color& c = options.vertex_colors[v];
            write_vec(out, "v", {p.x, p.y, p.z, c.r, c.g, c.b}, precision);
        } else {
            write_vec(out, "v", {p.x, p.y, p.z}, precision);
        }
    }
    if (uvs)
        for (const Vec2& t : mesh.uvs) write_vec(out, "vt", {t.x, t.y}, precision);
    if (normals)
        for (const Vec3& n : mesh.normals) write_vec(out, "vn", {n.x, n.y, n.z}, precision);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        out += 'f';
        for (std::size_t k = mesh.face_offsets[f]; k < mesh.face_offsets[f + 1]; ++k) {
            const std::uint64_t v = mesh.face_indices[k] + std::uint64_t{1};
            out += ' ';
            append_uint(out, v);
            if (uvs || normals) {
                out += '/';
                if (uvs) append_uint(out, mesh.uv_indices[k] + std::uint64_t{1});
                if (normals) {
                    out += '/';
                    append_uint(out, v);  // one normal per vertex, same numbering
                }
            }
        }
        out += '\n';
    }
    if (options.write_tags) {
        const SubdivisionTags& tags = mesh.tags;
        for (const Crease& c : tags.creases) {
            out += "t crease 2/1/0 ";
            append_uint(out, c.v0);
            out += ' ';
            append_uint(out, c.v1);
            out += ' ';
            io_detail::append_double(out, c.sharpness, precision);
            out += '\n';
        }
        for (const Corner& c : tags.corners) {
            out += "t corner 1/1/0 ";
            append_uint(out, c.vertex);
            out += ' ';
            io_detail::append_double(out, c.sharpness, precision);
            out += '\n';
        }
        if (!tags.holes.empty()) {
            out += "t hole ";
            append_uint(out, tags.holes.size());
            out += "/0/0";
            for (Index h : tags.holes) {
                out += ' ';
                append_uint(out, h);
            }
            out += '\n';
        }
        if (tags.boundary) {
            out += "t interpolateboundary 1/0/0 ";
            switch (*tags.boundary) {
                case BoundaryInterpolation::None: out += '0'; break;
                case BoundaryInterpolation::EdgeAndCorner: out += '1'; break;
                case BoundaryInterpolation::EdgeOnly: out += '2'; break;
            }
            out += '\n';
        }
    }
    return out;
}

}  // namespace surfaced
