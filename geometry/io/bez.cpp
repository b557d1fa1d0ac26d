// Geomview BEZ / BBP reader (see bez.h for the format) and the built-in patch samples.
#include "geometry/io/bez.h"

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "geometry/io/text_encoding.h"
#include "geometry/io/text_scanner.h"

namespace surfaced {
namespace {

using io_detail::error_at_line;
using io_detail::NumberStatus;
using io_detail::quote;

#include "geometry/io/samples/teapot32_bez.inc"

struct PatchType {
    int degree_u = 3, degree_v = 3, dimension = 3;
    bool texcoords = false;  //!< ST: 4 (s, t) pairs per patch
    bool colors = false;     //!< C: 4 RGBA colours per patch
};

bool is_digit(char c) { return c >= '0' && c <= '9'; }

enum class HeaderStatus { Ok, NotHeader, BadDegree, BadDimension };

//! `[ST]BBP` or `[C]BEZ<Nu><Nv><Nd>[_ST]`.
HeaderStatus parse_header(std::string_view token, PatchType& type) {
    type = PatchType{};
    if (token == "BBP" || token == "STBBP") {
        type.texcoords = token.starts_with("ST");
        return HeaderStatus::Ok;
    }
    if (token.starts_with("C")) {
        type.colors = true;
        token.remove_prefix(1);
    }
    if (!token.starts_with("BEZ")) return HeaderStatus::NotHeader;
    token.remove_prefix(3);
    if (token.ends_with("_ST")) {
        type.texcoords = true;
        token.remove_suffix(3);
    }
    if (token.size() != 3 || !is_digit(token[0]) || !is_digit(token[1]) || !is_digit(token[2]))
        return HeaderStatus::NotHeader;
    type.degree_u = token[0] - '0';
    type.degree_v = token[1] - '0';
    type.dimension = token[2] - '0';
    if (type.degree_u < 1 || type.degree_u > 6 || type.degree_v < 1 || type.degree_v > 6)
        return HeaderStatus::BadDegree;
    if (type.dimension != 3 && type.dimension != 4) return HeaderStatus::BadDimension;
    return HeaderStatus::Ok;
}

class BezReader {
public:
    BezReader(std::string_view text, const BezReadOptions& options) : text_(text), options_(options) {}

    Result<PatchSet> read() {
        auto start = io_detail::check_text_encoding(text_);
        if (!start) return start.error();
        io_detail::TokenReader tokens(text_, *start, '#');

        std::string_view token;
        if (!tokens.next(token)) return make_error(ErrorCode::ParseError, "empty file (only comments or whitespace)");
        PatchType type;
        if (auto header = check_header(token, tokens.line(), type); !header) return header.error();

        while (tokens.next(token)) {
            // a new header keyword changes the type of the patches that follow
            if (!token.empty() && (token[0] == 'B' || token[0] == 'C' || token[0] == 'S')) {
                if (auto header = check_header(token, tokens.line(), type); !header) return header.error();
                continue;
            }
            if (set_.patches.size() >= options_.max_patches)
                return error_at_line(ErrorCode::BudgetExceeded, tokens.line(),
                                     "more than max_patches (" + std::to_string(options_.max_patches) + ") patches");
            if (auto patch = read_patch(tokens, token, type); !patch) return patch.error();
        }
        if (set_.patches.empty())
            return error_at_line(ErrorCode::ParseError, tokens.line(), "no patches after the header");
        return std::move(set_);
    }

private:
    Status check_header(std::string_view token, std::int64_t line, PatchType& type) {
        switch (parse_header(token, type)) {
            case HeaderStatus::Ok: break;
            case HeaderStatus::NotHeader:
                return error_at_line(
                    ErrorCode::ParseError, line,
                    "expected a BEZ header ([ST]BBP or [C]BEZ<Nu><Nv><Nd>[_ST]), found " + quote(token));
            case HeaderStatus::BadDegree:
                return error_at_line(ErrorCode::ParseError, line, "header " + quote(token) + ": degrees must be 1..6");
            case HeaderStatus::BadDimension:
                return error_at_line(ErrorCode::ParseError, line,
                                     "header " + quote(token) + ": dimension must be 3 or 4");
        }
        return Ok{};
    }

    //! Reads one number; `first` is an already-read token to use instead of reading one.
    Status number(io_detail::TokenReader& tokens, std::string_view* first, double& out, const std::string& what) {
        std::string_view token;
        if (first) {
            token = *first;
        } else if (!tokens.next(token)) {
            return error_at_line(
                ErrorCode::ParseError, tokens.line(),
                "unexpected end of file in patch " + std::to_string(set_.patches.size()) + ": no " + what);
        }
        if (io_detail::parse_double(token, out) != NumberStatus::Ok)
            return error_at_line(
                ErrorCode::ParseError, tokens.line(),
                "patch " + std::to_string(set_.patches.size()) + ": " + what + " " + quote(token) + " is not a number");
        if (!std::isfinite(out))
            return error_at_line(ErrorCode::NonFinite, tokens.line(),
                                 "patch " + std::to_string(set_.patches.size()) + ": " + what + " is not finite");
        return Ok{};
    }

    Status read_patch(io_detail::TokenReader& tokens, std::string_view first, const PatchType& type) {
        BezierPatch patch;
        patch.degree_u = type.degree_u;
        patch.degree_v = type.degree_v;
        const int count = (type.degree_u + 1) * (type.degree_v + 1);
        patch.points.resize(static_cast<std::size_t>(count));
        std::string_view* pending = &first;
        const std::int64_t first_line = tokens.line();
        for (int k = 0; k < count; ++k) {
            const std::string what = "control point " + std::to_string(k) + " coordinate";
            Vec3& point = patch.points[static_cast<std::size_t>(k)];
            for (int c = 0; c < 3; ++c) {
                if (auto ok = number(tokens, pending, point[c], what); !ok) return ok;
                pending = nullptr;
            }
            if (type.dimension == 4) {
                // homogeneous (x, y, z, w) as geomview's HPoint3: the control point is (x, y, z) / w, weight w
                double w = 0;
                if (auto ok = number(tokens, nullptr, w, "control point " + std::to_string(k) + " weight"); !ok)
                    return ok;
                if (!(w > 0))
                    return error_at_line(ErrorCode::InvalidArgument, tokens.line(),
                                         "patch " + std::to_string(set_.patches.size()) + ": control point " +
                                             std::to_string(k) + " weight (4th coordinate) must be > 0");
                point = point * (1.0 / w);
                if (!is_finite(point))
                    return error_at_line(ErrorCode::NonFinite, tokens.line(),
                                         "patch " + std::to_string(set_.patches.size()) + ": control point " +
                                             std::to_string(k) + " divided by its weight is not finite");
                patch.weights.push_back(w);
            }
        }
        if (type.dimension == 4) {
            // the geometric checks (weight ratio, overflow) with this file's line
            if (auto valid = validate(std::span<const BezierPatch>(&patch, 1)); !valid) {
                const std::string message = valid.error().message;  // "patch 0: ..."
                const std::size_t colon = message.find(": ");
                return error_at_line(valid.error().code, first_line,
                                     "patch " + std::to_string(set_.patches.size()) +
                                         (colon == std::string::npos ? ": " + message : message.substr(colon)));
            }
        }
        double ignored = 0;
        if (type.texcoords) {
            std::array<Vec2, 4> corners;
            for (int k = 0; k < 8; ++k)
                if (auto ok = number(tokens, nullptr, k % 2 ? corners[k / 2].y : corners[k / 2].x,
                                     "corner texture coordinate");
                    !ok)
                    return ok;
            patch.corner_uvs = corners;
        }
        if (type.colors)
            for (int k = 0; k < 16; ++k)
                if (auto ok = number(tokens, nullptr, ignored, "corner colour component"); !ok) return ok;
        set_.patches.push_back(std::move(patch));
        return Ok{};
    }

    std::string_view text_;
    const BezReadOptions& options_;
    PatchSet set_;
};

constexpr std::string_view kSampleNames[] = {"teapot"};

}  // namespace

Result<PatchSet> read_bez(std::string_view text, const BezReadOptions& options) {
    return io_detail::with_text(
        text, [&](std::string_view decoded, io_detail::TextEncoding) { return BezReader(decoded, options).read(); });
}

std::span<const std::string_view> patch_sample_names() { return kSampleNames; }

std::string_view patch_sample_text(std::string_view name) {
    if (name == "teapot") return {kTeapot32Bez, sizeof(kTeapot32Bez) - 1};
    return {};
}

}  // namespace surfaced
