// libFuzzer target: SVG path data (geometry/curves/svg_path.h parse_svg_path), with arcs as rational quadratics and
// as cubics. Beyond "no crash, no sanitizer report, no hang": an error is a located ParseError (offset inside the
// data, message naming it) or a BudgetExceeded; accepted chains pass validate(), their pieces meet bit-exactly, and
// the chain operations (continuity report, C1 enforcement of the polynomial form, tessellation within a segment
// budget) run on them without crashing.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "geometry/curves/piecewise.h"
#include "geometry/curves/svg_path.h"

namespace {

void check_chains(std::string_view text, const surfaced::SvgPathOptions& options) {
    using namespace surfaced;
    const auto result = parse_svg_path(text, options);
    if (!result.ok()) {
        const GeoError& e = result.error();
        if (e.message.empty()) fuzz::fail("parse_svg_path error", "empty message");
        if (e.code != ErrorCode::ParseError && e.code != ErrorCode::BudgetExceeded)
            fuzz::fail("parse_svg_path error code", e.message);
        if (e.offset < 0 || static_cast<std::size_t>(e.offset) > text.size())
            fuzz::fail("parse_svg_path error offset", e.message);
        if (e.message.rfind("svg path: offset " + std::to_string(e.offset) + ": ", 0) != 0)
            fuzz::fail("parse_svg_path message does not start with its offset", e.message);
        for (char c : e.message)
            if (static_cast<unsigned char>(c) >= 0x80) fuzz::fail("parse_svg_path message is not ASCII", e.message);
        return;
    }
    std::size_t pieces = 0;
    for (const BezierChain& chain : *result) {
        if (const Status valid = validate(chain); !valid.ok())
            fuzz::fail("chain fails validate()", valid.error().message);
        for (std::size_t i = 1; i < chain.pieces.size(); ++i)
            if (chain.pieces[i].points.front() != chain.pieces[i - 1].points.back())
                fuzz::fail("pieces do not meet", std::to_string(i));
        pieces += chain.pieces.size();
        if (!continuity(chain).ok()) fuzz::fail("continuity() rejects a parsed chain", "");
        if (options.arcs == SvgArcConversion::Cubic && !enforce_c1(chain).ok())
            fuzz::fail("enforce_c1 rejects a polynomial chain", "");
        ChainTessellationOptions tess;
        tess.tolerance = 1e-2;
        tess.max_segments = 2'000;
        const auto t = tessellate(chain, tess);
        if (!t.ok() && t.error().code != ErrorCode::BudgetExceeded) fuzz::fail("tessellate error", t.error().message);
    }
    if (pieces > options.max_pieces) fuzz::fail("more pieces than max_pieces", std::to_string(pieces));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    SvgPathOptions options;
    options.max_commands = 4'000;
    options.max_pieces = 4'000;
    check_chains(text, options);
    options.arcs = SvgArcConversion::Cubic;
    options.arc_tolerance = 1e-3;
    check_chains(text, options);
    return 0;
}
