// Object File Format (Geomview OFF) reader and writer. Reader: ascii OFF with the C/N/ST prefixes (colours, normals, texture
// coordinates after each vertex, which are skipped), counts on the header line or the next one, `#` comments.
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

enum class HeaderKind { Off, NotOff, Unsupported };

//! [ST][C][N][4][n]OFF: the prefixes only add per-vertex data we skip, but 4D and n-dimensional vertices
//! change the number of coordinates, which we do not support.
HeaderKind classify_header(std::string_view token) {
    if (token.size() < 3 || token.substr(token.size() - 3) != "OFF") return HeaderKind::NotOff;
    std::string_view prefix = token.substr(0, token.size() - 3);
    if (prefix.starts_with("ST")) prefix.remove_prefix(2);
    if (prefix.starts_with("C")) prefix.remove_prefix(1);
    if (prefix.starts_with("N")) prefix.remove_prefix(1);
    if (prefix.empty()) return HeaderKind::Off;
    if (prefix == "4" || prefix == "n" || prefix == "4n") return HeaderKind::Unsupported;
    return HeaderKind::NotOff;
}

class OffReader {
public:
    OffReader(std::string_view text, const ReadOptions& options, ReadReport* report)
        : text_(text), options_(options), report_(report) {}

    Result<PolygonMesh> read() {
        auto start = io_detail::check_text_encoding(text_);
        if (!start) return start.error();
        io_detail::TokenReader tokens(text_, *start, '#');
        std::uint64_t nv = 0, nf = 0;
        if (auto error = read_counts(tokens, nv, nf)) return std::move(*error);
        if (auto error = read_vertices(tokens, nv)) return std::move(*error);
        if (auto error = read_faces(tokens, nf)) return std::move(*error);
        return std::move(mesh_);
    }

private:
    //! The header keyword (optional in the format: a file may start with the counts) and "vertices faces [edges]",
    //! checked against the bytes that follow and the budgets before anything is reserved.
    std::optional<GeoError> read_counts(io_detail::TokenReader& tokens, std::uint64_t& nv, std::uint64_t& nf) {
        std::string_view token;
        if (!tokens.next(token)) return make_error(ErrorCode::ParseError, "empty file (only comments or whitespace)");
        const HeaderKind kind = classify_header(token);
        if (kind == HeaderKind::Unsupported)
            return error_at_line(ErrorCode::Unsupported, tokens.line(),
                                 quote(token) + " (4D or n-dimensional OFF) is not supported");
        bool have_token = false;
        if (kind == HeaderKind::NotOff) {
            std::int64_t probe = 0;
            if (io_detail::parse_int(token, probe) != NumberStatus::Ok)
                return error_at_line(ErrorCode::ParseError, tokens.line(),
                                     "expected an OFF header, found " + quote(token));
            have_token = true;  // headerless file: this is the vertex count
        } else if (tokens.next_on_line(token)) {
            if (token == "BINARY")
                return error_at_line(ErrorCode::Unsupported, tokens.line(), "binary OFF is not supported");
            have_token = true;  // counts on the header line
        }

        std::int64_t counts[2] = {0, 0};
        const char* names[2] = {"vertex count", "face count"};
        for (int i = 0; i < 2; ++i) {
            if (!have_token && !tokens.next(token))
                return error_at_line(ErrorCode::ParseError, tokens.line(),
                                     std::string("unexpected end of file: no ") + names[i]);
            have_token = false;
            const auto status = io_detail::parse_int(token, counts[i]);
            if (status != NumberStatus::Ok || counts[i] < 0)
                return error_at_line(ErrorCode::ParseError, tokens.line(),
                                     std::string(names[i]) + " " + quote(token) + " is not a non-negative integer");
        }
        const std::int64_t header_line = tokens.line();
        tokens.skip_line();  // the edge count, which nothing uses
        nv = static_cast<std::uint64_t>(counts[0]);
        nf = static_cast<std::uint64_t>(counts[1]);
        if (nf == 0) return error_at_line(ErrorCode::ParseError, header_line, "no faces (header declares 0)");
        // Every vertex needs at least "x y z" plus a separator (6 bytes) and every face "3 a b c" (8); a header
        // that promises more than the bytes can hold is rejected before anything is reserved (and before the
        // budget check: a 200-byte file claiming 4e9 vertices is malformed, not merely large).
        const std::uint64_t remaining = tokens.remaining_bytes();
        if (nv > remaining / 6 + 1 || nf > remaining / 8 + 1 || nv * 6 + nf * 8 > remaining + 2)
            return error_at_line(ErrorCode::ParseError, header_line,
                                 "header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                                     " faces, but only " + std::to_string(remaining) + " bytes follow");
        if (nv > options_.max_vertices)
            return error_at_line(ErrorCode::BudgetExceeded, header_line,
                                 "header declares " + std::to_string(nv) + " vertices, more than max_vertices (" +
                                     std::to_string(options_.max_vertices) + ")");
        if (nf > options_.max_faces)
            return error_at_line(ErrorCode::BudgetExceeded, header_line,
                                 "header declares " + std::to_string(nf) + " faces, more than max_faces (" +
                                     std::to_string(options_.max_faces) + ")");
        mesh_.positions.reserve(nv);
        mesh_.face_offsets.reserve(nf + 1);
        mesh_.face_indices.reserve(io_detail::bounded_reserve(nf * 4, remaining / 2));
        return std::nullopt;
    }

    //! nv lines "x y z [colour, normal, texture coordinate]".
    std::optional<GeoError> read_vertices(io_detail::TokenReader& tokens, std::uint64_t nv) {
        std::string_view token;
        for (std::uint64_t v = 0; v < nv; ++v) {
            Vec3 p;
            for (int i = 0; i < 3; ++i) {
                if (!tokens.next(token))
                    return error_at_line(ErrorCode::ParseError, tokens.line(),
                                         "unexpected end of file: read " + std::to_string(v) + " of " +
                                             std::to_string(nv) + " vertices");
                if (auto status = io_detail::parse_double(token, p[i]); status != NumberStatus::Ok)
                    return error_at_line(ErrorCode::ParseError, tokens.line(),
                                         "vertex coordinate " + quote(token) + " is not a number");
            }
            if (!is_finite(p))
                return error_at_line(ErrorCode::NonFinite, tokens.line(),
                                     "vertex " + std::to_string(v) + " has a non-finite coordinate");
            tokens.skip_line();  // colour, normal, texture coordinate
            mesh_.positions.push_back(p);
        }
        return std::nullopt;
    }

    //! nf lines "n i_1 ... i_n [colour]", each face's indices on its own line.
    std::optional<GeoError> read_faces(io_detail::TokenReader& tokens, std::uint64_t nf) {
        const std::uint64_t nv = mesh_.positions.size();
        std::string_view token;
        std::vector<Index> face, scratch;
        for (std::uint64_t f = 0; f < nf; ++f) {
            std::int64_t n = 0;
            if (!tokens.next(token))
                return error_at_line(
                    ErrorCode::ParseError, tokens.line(),
                    "unexpected end of file: read " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
            const std::int64_t line = tokens.line();
            if (io_detail::parse_int(token, n) != NumberStatus::Ok || n < 0)
                return error_at_line(ErrorCode::ParseError, line,
                                     "face vertex count " + quote(token) + " is not a non-negative integer");
            if (static_cast<std::uint64_t>(n) > options_.max_face_size)
                return error_at_line(ErrorCode::BudgetExceeded, line,
                                     "face has " + std::to_string(n) + " vertices, more than max_face_size (" +
                                         std::to_string(options_.max_face_size) + ")");
            if (n < 3)
                return error_at_line(ErrorCode::DegenerateFace, line,
                                     "face has " + std::to_string(n) + " vertices (at least 3 needed)");
            face.clear();
            for (std::int64_t k = 0; k < n; ++k) {
                // Indices stay on the face's line: running onto the next line means the count is wrong.
                if (!tokens.next_on_line(token))
                    return error_at_line(
                        ErrorCode::ParseError, line,
                        "face declares " + std::to_string(n) + " vertices but lists " + std::to_string(k));
                std::int64_t index = 0;
                const auto status = io_detail::parse_int(token, index);
                if (status == NumberStatus::Invalid)
                    return error_at_line(ErrorCode::ParseError, line,
                                         "face index " + quote(token) + " is not an integer");
                if (status == NumberStatus::OutOfRange || index < 0 || static_cast<std::uint64_t>(index) >= nv)
                    return error_at_line(
                        ErrorCode::IndexOutOfRange, line,
                        "face index " + std::string(token) + " out of range (" + std::to_string(nv) + " vertices)");
                face.push_back(static_cast<Index>(index));
            }
            if (!options_.allow_repeated_vertices) {
                if (auto dup = io_detail::repeated_vertex(face, scratch))
                    return error_at_line(ErrorCode::DegenerateFace, line,
                                         "face uses vertex " + std::to_string(*dup) + " more than once");
            }
            if (mesh_.face_indices.size() + face.size() > io_detail::kMaxIndexCount)
                return error_at_line(ErrorCode::BudgetExceeded, line, "more than 2^32 face corners");
            tokens.skip_line();  // optional face colour
            mesh_.add_face(face);
            io_detail::record_face_line(report_, line);
        }
        return std::nullopt;
    }

    std::string_view text_;
    const ReadOptions& options_;
    ReadReport* report_;
    PolygonMesh mesh_;
};

}  // namespace

Result<PolygonMesh> read_off(std::string_view text, const ReadOptions& options) {
    return read_off(text, options, nullptr);
}

Result<PolygonMesh> read_off(std::string_view text, const ReadOptions& options, ReadReport* report) {
    return io_detail::with_text(text, [&](std::string_view decoded, io_detail::TextEncoding) {
        return OffReader(decoded, options, report).read();
    });
}

std::string write_off(const PolygonMesh& mesh) {
    using io_detail::append_uint;
    std::string out;
    out.reserve(32 + mesh.positions.size() * 60 + mesh.face_indices.size() * 8 + mesh.face_count() * 4);
    out += "OFF\n";
    append_uint(out, mesh.positions.size());
    out += ' ';
    append_uint(out, mesh.face_count());
    out += " 0\n";
    for (const Vec3& p : mesh.positions) {
        append_number_text(out, p.x);
        out += ' ';
        append_number_text(out, p.y);
        out += ' ';
        append_number_text(out, p.z);
        out += '\n';
    }
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        append_uint(out, face.size());
        for (Index v : face) {
            out += ' ';
            append_uint(out, v);
        }
        out += '\n';
    }
    return out;
}

}  // namespace surfaced
