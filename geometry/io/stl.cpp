// STL reader (ascii and binary) and binary writer. STL stores each triangle with its own three corners; the reader
// welds corners whose coordinates are exactly equal into shared vertices, so the result has real connectivity.
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/io/format_common.h"
#include "geometry/io/mesh_io.h"
#include "geometry/io/text_encoding.h"
#include "geometry/io/text_scanner.h"
#include "geometry/mesh/triangulate.h"

namespace surfaced {
namespace {

using io_detail::error_at_line;
using io_detail::error_at_offset;
using io_detail::iequals;
using io_detail::NumberStatus;
using io_detail::quote;

constexpr std::size_t kBinaryHeader = 84;    // 80-byte header + uint32 triangle count
constexpr std::size_t kBinaryTriangle = 50;  // normal, 3 corners (12 floats) + uint16 attribute

//! Maps exact positions to vertex indices with open addressing over the mesh's own position array, so a
//! position is stored once (no key copies) and lookups cost one hash and usually one compare.
class Welder {
public:
    explicit Welder(std::vector<Vec3>& positions) : positions_(positions) { rehash(64); }

    //! Index of `p`, adding it when new. -0.0 and 0.0 weld (they compare equal).
    Index find_or_add(const Vec3& p) {
        if ((used_ + 1) * 2 > slots_.size()) rehash(slots_.size() * 2);
        std::size_t i = hash(p) & mask_;
        while (slots_[i] != kInvalidIndex) {
            if (positions_[slots_[i]] == p) return slots_[i];
            i = (i + 1) & mask_;
        }
        const auto index = static_cast<Index>(positions_.size());
        positions_.push_back(p);
        slots_[i] = index;
        ++used_;
        return index;
    }
    void reserve(std::size_t vertices) {
        std::size_t capacity = 64;
        while (capacity < vertices * 2) capacity *= 2;
        if (capacity > slots_.size()) rehash(capacity);
    }

private:
    static std::uint64_t mix(double v) {
        std::uint64_t bits = std::bit_cast<std::uint64_t>(v + 0.0);  // + 0.0 turns -0.0 into 0.0
        bits ^= bits >> 33;
        bits *= 0xff51afd7ed558ccdULL;
        bits ^= bits >> 33;
        return bits;
    }
    static std::size_t hash(const Vec3& p) {
        return static_cast<std::size_t>(mix(p.x) * 31 + mix(p.y) * 0x9e3779b97f4a7c15ULL +
                                        (mix(p.z) ^ (mix(p.z) >> 29)));
    }
    void rehash(std::size_t capacity) {
        slots_.assign(capacity, kInvalidIndex);
        mask_ = capacity - 1;
        for (Index v = 0; v < positions_.size(); ++v) {
            std::size_t i = hash(positions_[v]) & mask_;
            while (slots_[i] != kInvalidIndex) i = (i + 1) & mask_;
            slots_[i] = v;
        }
    }

    std::vector<Vec3>& positions_;
    std::vector<Index> slots_;
    std::size_t mask_ = 0;
    std::size_t used_ = 0;
};

//! Collects triangles: welds their corners and drops those that are degenerate by index (two equal corners).
class TriangleSink {
public:
    TriangleSink(const ReadOptions& options, std::size_t expected_triangles)
        : options_(options), welder_(mesh_.positions) {
        mesh_.face_offsets.reserve(expected_triangles + 1);
        mesh_.face_indices.reserve(expected_triangles * 3);
        // Closed triangle meshes have about half as many vertices as triangles.
        mesh_.positions.reserve(expected_triangles / 2 + 3);
        welder_.reserve(expected_triangles / 2 + 3);
    }

    //! Returns a message for BudgetExceeded, or nullopt.
    std::optional<std::string> add(const Vec3 (&corners)[3]) {
        ++triangles_;
        if (corners[0] == corners[1] || corners[1] == corners[2] || corners[0] == corners[2]) {
            return std::nullopt;
        }
        if (mesh_.face_count() >= options_.max_faces)
            return "more than max_faces (" + std::to_string(options_.max_faces) + ") triangles";
        Index face[3];
        for (int i = 0; i < 3; ++i) {
            face[i] = welder_.find_or_add(corners[i]);
            if (mesh_.positions.size() > options_.max_vertices)
                return "more than max_vertices (" + std::to_string(options_.max_vertices) + ") distinct vertices";
        }
        mesh_.add_face({face[0], face[1], face[2]});
        return std::nullopt;
    }

    Result<PolygonMesh> finish() {
        if (mesh_.face_count() == 0) {
            if (triangles_ == 0) return make_error(ErrorCode::ParseError, "no faces (the file has no triangles)");
            return make_error(ErrorCode::DegenerateFace,
                              "no faces: all " + std::to_string(triangles_) + " triangles are degenerate");
        }
        return std::move(mesh_);
    }

private:
    const ReadOptions& options_;
    PolygonMesh mesh_;
    Welder welder_;
    std::size_t triangles_ = 0;
};

float load_float_le(const char* p) {
    std::uint32_t bits = 0;
    for (int i = 3; i >= 0; --i) bits = (bits << 8) | static_cast<unsigned char>(p[i]);
    return std::bit_cast<float>(bits);
}

std::uint32_t load_u32_le(const char* p) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(p[i]);
    return v;
}

Result<PolygonMesh> read_binary(std::string_view bytes, const ReadOptions& options) {
    const std::uint64_t count = load_u32_le(bytes.data() + 80);
    const std::uint64_t expected = kBinaryHeader + count * kBinaryTriangle;
    if (bytes.size() < expected)
        return error_at_offset(ErrorCode::ParseError, 80,
                               "binary STL declares " + std::to_string(count) + " triangles (" +
                                   std::to_string(expected) + " bytes) but the file has " +
                                   std::to_string(bytes.size()) + " bytes");
    if (count > options.max_faces)
        return error_at_offset(ErrorCode::BudgetExceeded, 80,
                               "binary STL declares " + std::to_string(count) + " triangles, more than max_faces (" +
                                   std::to_string(options.max_faces) + ")");
    TriangleSink sink(options, count);  // count is backed by the bytes checked above
    for (std::uint64_t t = 0; t < count; ++t) {
        const std::size_t offset = kBinaryHeader + t * kBinaryTriangle;
        const char* p = bytes.data() + offset + 12;  // skip the facet normal, which is recomputable
        Vec3 corners[3];
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) corners[c][k] = load_float_le(p + 12 * c + 4 * k);
        for (int c = 0; c < 3; ++c)
            if (!is_finite(corners[c]))
                return error_at_offset(ErrorCode::NonFinite, static_cast<std::int64_t>(offset + 12 + 12 * c),
                                       "triangle " + std::to_string(t) + " has a non-finite coordinate");
        if (auto budget = sink.add(corners))
            return error_at_offset(ErrorCode::BudgetExceeded, static_cast<std::int64_t>(offset), *budget);
    }
    return sink.finish();
}

Result<PolygonMesh> read_ascii(std::string_view bytes, const ReadOptions& options) {
    auto start = io_detail::check_text_encoding(bytes);
    if (!start) return start.error();
    // An ascii facet is at least ~100 bytes; a smaller divisor only over-reserves a little.
    TriangleSink sink(options, io_detail::bounded_reserve(bytes.size() / 128, options.max_faces));
    io_detail::TokenReader tokens(bytes, *start);
    std::string_view token;

    auto expect = [&](std::string_view keyword) -> std::optional<GeoError> {
        if (!tokens.next(token))
            return error_at_line(ErrorCode::ParseError, tokens.line(),
                                 "unexpected end of file (expected '" + std::string(keyword) + "')");
        if (!iequals(token, keyword))
            return error_at_line(ErrorCode::ParseError, tokens.line(),
                                 "expected '" + std::string(keyword) + "', found " + quote(token));
        return std::nullopt;
    };
    auto numbers = [&](Vec3& v, const char* what) -> std::optional<GeoError> {
        for (int k = 0; k < 3; ++k) {
            if (!tokens.next_on_line(token))
                return error_at_line(ErrorCode::ParseError, tokens.line(), std::string(what) + " needs 3 numbers");
            if (io_detail::parse_double(token, v[k]) != NumberStatus::Ok)
                return error_at_line(ErrorCode::ParseError, tokens.line(),
                                     std::string(what) + " value " + quote(token) + " is not a number");
        }
        return std::nullopt;
    };

    if (auto error = expect("solid")) return std::move(*error);
    tokens.skip_line();  // the solid's name
    // A file may hold several solids one after another; all their triangles go into one mesh.
    while (true) {
        if (!tokens.next(token))
            return error_at_line(ErrorCode::ParseError, tokens.line(), "unexpected end of file (no 'endsolid')");
        if (iequals(token, "endsolid")) {
            tokens.skip_line();
            if (!tokens.next(token)) break;
            if (!iequals(token, "solid"))
                return error_at_line(ErrorCode::ParseError, tokens.line(),
                                     "expected 'solid' or end of file, found " + quote(token));
            tokens.skip_line();
            continue;
        }
        if (!iequals(token, "facet"))
            return error_at_line(ErrorCode::ParseError, tokens.line(),
                                 "expected 'facet' or 'endsolid', found " + quote(token));
        const std::int64_t facet_line = tokens.line();
        tokens.skip_line();  // "normal nx ny nz": recomputable, not kept
        if (auto error = expect("outer")) return std::move(*error);
        if (auto error = expect("loop")) return std::move(*error);
        Vec3 corners[3];
        int n = 0;
        while (true) {
            if (!tokens.next(token))
                return error_at_line(ErrorCode::ParseError, tokens.line(), "unexpected end of file inside a facet");
            if (iequals(token, "endloop")) break;
            if (!iequals(token, "vertex"))
                return error_at_line(ErrorCode::ParseError, tokens.line(),
                                     "expected 'vertex' or 'endloop', found " + quote(token));
            if (n == 3)
                return error_at_line(ErrorCode::ParseError, tokens.line(),
                                     "facet has more than 3 vertices (STL facets are triangles)");
            if (auto error = numbers(corners[n], "vertex")) return std::move(*error);
            if (!is_finite(corners[n]))
                return error_at_line(ErrorCode::NonFinite, tokens.line(), "vertex has a non-finite coordinate");
            ++n;
        }
        if (n < 3)
            return error_at_line(ErrorCode::DegenerateFace, facet_line,
                                 "facet has " + std::to_string(n) + " vertices (3 needed)");
        if (auto error = expect("endfacet")) return std::move(*error);
        if (auto budget = sink.add(corners)) return error_at_line(ErrorCode::BudgetExceeded, facet_line, *budget);
    }
    return sink.finish();
}

bool starts_with_solid(std::string_view bytes) {
    std::size_t i = 0;
    if (bytes.size() >= 3 && bytes.substr(0, 3) == "\xef\xbb\xbf") i = 3;
    while (i < bytes.size() && (io_detail::is_space(bytes[i]) || bytes[i] == '\n')) ++i;
    return bytes.size() - i >= 5 && iequals(bytes.substr(i, 5), "solid");
}

//! A byte order mark, or ASCII text with every other byte NUL.
bool looks_like_utf16(std::string_view bytes) {
    if (bytes.size() < 4) return false;
    const auto b0 = static_cast<unsigned char>(bytes[0]), b1 = static_cast<unsigned char>(bytes[1]);
    if ((b0 == 0xff && b1 == 0xfe) || (b0 == 0xfe && b1 == 0xff)) return true;
    return (bytes[1] == 0 && bytes[3] == 0 && bytes[0] != 0 && bytes[2] != 0) ||
           (bytes[0] == 0 && bytes[2] == 0 && bytes[1] != 0 && bytes[3] != 0);
}

}  // namespace

Result<PolygonMesh> read_stl(std::string_view bytes, const ReadOptions& options) {
    if (bytes.empty()) return make_error(ErrorCode::ParseError, "empty file", -1, 0);
    // The size rule decides, not the word "solid": many binary exporters start their 80-byte header with it.
    if (bytes.size() >= kBinaryHeader &&
        kBinaryHeader + std::uint64_t{load_u32_le(bytes.data() + 80)} * kBinaryTriangle == bytes.size())
        return read_binary(bytes, options);
    // UTF-16 with a byte order mark is read as the ascii STL it spells; without one, check_text_encoding says why not.
    if (looks_like_utf16(bytes))
        return io_detail::with_text(
            bytes, [&](std::string_view text, io_detail::TextEncoding) { return read_ascii(text, options); });
    // "solid" with NUL bytes after it is a binary file with a misleading header (and a wrong size).
    if (starts_with_solid(bytes) && (bytes.size() < kBinaryHeader || !std::memchr(bytes.data(), 0, bytes.size())))
        return read_ascii(bytes, options);
    if (bytes.size() < kBinaryHeader)
        return error_at_offset(ErrorCode::ParseError, 0,
                               "not an ascii STL (no 'solid') and too short for a binary STL (" +
                                   std::to_string(bytes.size()) + " bytes, at least 84 needed)");
    // Not ascii, so binary whose size does not match its count: truncated (error) or padded (read, extra ignored).
    return read_binary(bytes, options);
}

namespace {

void store_u32_le(std::string& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
}

void store_float_le(std::string& out, double v) {
    store_u32_le(out, std::bit_cast<std::uint32_t>(static_cast<float>(v)));
}

void store_vec_le(std::string& out, const Vec3& v) {
    store_float_le(out, v.x);
    store_float_le(out, v.y);
    store_float_le(out, v.z);
}

}  // namespace

std::string write_stl(const PolygonMesh& polygons) {
    bool all_triangles = true;
    for (std::size_t f = 0; f < polygons.face_count() && all_triangles; ++f) all_triangles = polygons.face_size(f) == 3;
    PolygonMesh triangulated;
    if (!all_triangles) triangulated = triangulate(polygons);
    const PolygonMesh& mesh = all_triangles ? polygons : triangulated;
    std::uint64_t triangles = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        if (mesh.face_size(f) >= 3) triangles += mesh.face_size(f) - 2;
    std::string out;
    out.reserve(kBinaryHeader + triangles * kBinaryTriangle);
    // The header must not start with "solid", which would make it look like ascii STL to some readers.
    std::string header = "binary STL written by surfaced";
    header.resize(80, ' ');
    out += header;
    store_u32_le(out, static_cast<std::uint32_t>(triangles));
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t k = 1; k + 1 < face.size(); ++k) {
            const Vec3& a = mesh.positions[face[0]];
            const Vec3& b = mesh.positions[face[k]];
            const Vec3& c = mesh.positions[face[k + 1]];
            const Vec3 n = cross(b - a, c - a);
            const double length = norm(n);
            // a degenerate triangle has no direction: STL readers recompute a zero normal from the corners
            store_vec_le(out, length > 0 && std::isfinite(length) ? n * (1.0 / length) : Vec3{0, 0, 0});
            store_vec_le(out, a);
            store_vec_le(out, b);
            store_vec_le(out, c);
            out += '\0';
            out += '\0';  // attribute byte count
        }
    }
    return out;
}

}  // namespace surfaced
