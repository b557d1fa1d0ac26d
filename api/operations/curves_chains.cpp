// POST /curves, chains of Bézier pieces and SVG path data (curves.h has the request): decoding, the continuity
// report and C1/G1 enforcement, the chain queries, and the answer.
#include <algorithm>
#include <cmath>
#include <exception>
#include <initializer_list>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "api/operations/curve_request.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "geometry/curves/svg_path.h"

namespace surfaced::api::operations::curve_request {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

// ---- chains and SVG paths ------------------------------------------------------------------------------------------

//! "chain": {"pieces": [{"points", "weights"?}, ...], "closed"?}; `dimension` from the first point.
ApiResult<BezierChain> decode_chain(const Json& value, std::size_t& dimension) {
    if (!value.is_object())
        return invalid("chain", R"(chain must be {"pieces": [{"points": [...]}, ...], "closed": b})");
    if (auto error = check_members(value, "chain", {"pieces", "closed"})) return std::move(*error);
    BezierChain chain;
    if (auto it = value.find("closed"); it != value.end()) {
        auto closed = read_bool(*it, "chain.closed");
        if (!closed) return std::move(closed.error());
        chain.closed = closed.value();
    }
    const auto pieces = value.find("pieces");
    if (pieces == value.end() || !pieces->is_array() || pieces->empty())
        return invalid("chain.pieces", "chain.pieces must be a non-empty array of {\"points\": [...]}");
    if (pieces->size() > kMaxChainPieces)
        return budget(
            "chain has " + std::to_string(pieces->size()) + " pieces; the limit is " + std::to_string(kMaxChainPieces),
            "chain.pieces");
    // shapes and sizes of every piece before reading any point
    std::size_t total = 0;
    for (std::size_t i = 0; i < pieces->size(); ++i) {
        const std::string path = index_path("chain.pieces", i);
        const Json& piece = (*pieces)[i];
        if (!piece.is_object()) return invalid(path, path + R"( must be {"points": [...], "weights"?: [...]})");
        if (auto error = check_members(piece, path, {"points", "weights"})) return std::move(*error);
        const auto points = piece.find("points");
        if (points == piece.end() || !points->is_array() || points->empty() || !(*points)[0].is_array())
            return invalid(path + ".points", path + ".points is required: an array of [x, y] or [x, y, z]");
        if (points->size() > static_cast<std::size_t>(kMaxCurveDegree) + 1)
            return budget(path + ".points has " + std::to_string(points->size()) +
                              " control points; the largest degree accepted is " + std::to_string(kMaxCurveDegree),
                          path + ".points");
        total += points->size();
    }
    if (total > kMaxChainPoints)
        return budget(
            "chain has " + std::to_string(total) + " control points; the limit is " + std::to_string(kMaxChainPoints),
            "chain.pieces");
    dimension = (*pieces)[0]["points"][0].size() == 2 ? 2 : 3;
    chain.pieces.resize(pieces->size());
    for (std::size_t i = 0; i < pieces->size(); ++i) {
        const std::string path = index_path("chain.pieces", i);
        const Json& piece = (*pieces)[i];
        BezierCurve& curve = chain.pieces[i];
        if (auto error = read_control_points(piece["points"], path + ".points", dimension, curve.points))
            return std::move(*error);
        if (auto it = piece.find("weights"); it != piece.end())
            if (auto error = read_weights(*it, path + ".weights", curve.points.size(), curve.weights))
                return std::move(*error);
    }
    if (Status s = validate(chain); !s) {
        const std::int64_t piece = s.error().element;
        return error_at(s.error(), piece >= 0 ? index_path("chain.pieces", static_cast<std::size_t>(piece)) : "chain");
    }
    return chain;
}

//! An SVG syntax error: 422 (the JSON is fine, the path data in it is not), field "svg", offset in the path data.
ApiError svg_error(const GeoError& error) {
    ApiError out = from_geo_error(error);
    out.field = "svg";
    if (error.code == ErrorCode::ParseError) {
        out.status = 422;
        out.title = "Malformed SVG path data";
    }
    return out;
}

ApiResult<std::vector<BezierChain>> decode_svg(const Json& value) {
    if (!value.is_string()) return invalid("svg", "svg must be a string of SVG path data (\"M 0 0 C 1 1 2 1 3 0\")");
    const auto& data = value.get_ref<const std::string&>();
    if (data.size() > kMaxSvgBytes)
        return budget("svg is " + std::to_string(data.size()) + " bytes; the limit is " + std::to_string(kMaxSvgBytes),
                      "svg");
    SvgPathOptions options;
    options.max_commands = kMaxSvgCommands;
    options.max_pieces = kMaxChainPieces;
    auto chains = parse_svg_path(data, options);
    if (!chains) return svg_error(chains.error());
    if (chains->empty()) return invalid("svg", "svg has no drawing segment (path data with only moves, or empty)");
    return std::move(chains.value());
}

struct ChainQueries {
    std::optional<ContinuityOptions> continuity;
    std::optional<EnforceOptions> enforce;
    std::optional<std::vector<double>> evaluate;
    std::optional<double> length;
    std::optional<double> tessellate;
    bool to_bezier = false;
};

constexpr EnumName<EnforceMode> kEnforceModeNames[] = {{"C1", EnforceMode::C1}, {"G1", EnforceMode::G1}};
constexpr EnumName<JointSide> kJointSideNames[] = {
    {"left", JointSide::Left}, {"right", JointSide::Right}, {"both", JointSide::Both}};

ApiResult<ContinuityOptions> read_continuity(const Json& value) {
    ContinuityOptions options;
    if (value.is_boolean()) return options;
    if (!value.is_object())
        return invalid(
            "continuity",
            R"(continuity must be true or {"position_tolerance", "angle_tolerance", "derivative_tolerance"})");
    if (auto error =
            check_members(value, "continuity", {"position_tolerance", "angle_tolerance", "derivative_tolerance"}))
        return std::move(*error);
    for (auto [name, target] : {std::pair<const char*, double*>{"position_tolerance", &options.position_tolerance},
                                {"angle_tolerance", &options.angle_tolerance},
                                {"derivative_tolerance", &options.derivative_tolerance}}) {
        if (auto it = value.find(name); it != value.end()) {
            const std::string field = member_path("continuity", name);
            auto v = read_number(*it, field);
            if (!v) return std::move(v.error());
            if (v.value() < 0) return invalid(field, field + " must be >= 0");
            *target = v.value();
        }
    }
    return options;
}

ApiResult<EnforceOptions> read_enforce(const Json& value, std::size_t max_joints) {
    if (!value.is_object())
        return invalid(
            "enforce_c1",
            R"(enforce_c1 must be {"mode": "C1" | "G1", "side": "left" | "right" | "both", "joints": [i, ...]})");
    if (auto error = check_members(value, "enforce_c1", {"mode", "side", "joints"})) return std::move(*error);
    EnforceOptions options;
    if (auto it = value.find("mode"); it != value.end()) {
        auto mode = read_enum(*it, "enforce_c1.mode", kEnforceModeNames);
        if (!mode) return std::move(mode.error());
        options.mode = mode.value();
    }
    if (auto it = value.find("side"); it != value.end()) {
        auto side = read_enum(*it, "enforce_c1.side", kJointSideNames);
        if (!side) return std::move(side.error());
        options.side = side.value();
    }
    if (auto it = value.find("joints"); it != value.end()) {
        if (!it->is_array()) return invalid("enforce_c1.joints", "enforce_c1.joints must be an array of joint indices");
        for (std::size_t i = 0; i < it->size(); ++i) {
            const std::string field = index_path("enforce_c1.joints", i);
            auto j = read_integer((*it)[i], field);
            if (!j) return std::move(j.error());
            if (j.value() < 0 || static_cast<std::size_t>(j.value()) >= max_joints)
                return invalid(field, field + " = " + std::to_string(j.value()) + " is not a joint (the chain has " +
                                          std::to_string(max_joints) + ")");
            options.joints.push_back(static_cast<std::size_t>(j.value()));
        }
    }
    return options;
}

std::size_t joint_count(const BezierChain& chain) { return chain.pieces.size() - 1 + (chain.closed ? 1 : 0); }

ApiResult<ChainQueries> read_chain_queries(const Json& root, const std::vector<BezierChain>& chains, bool svg) {
    ChainQueries q;
    if (auto it = root.find("continuity"); it != root.end()) {
        if (it->is_boolean() && !it->get<bool>()) {
            // false: not asked
        } else {
            auto options = read_continuity(*it);
            if (!options) return std::move(options.error());
            q.continuity = options.value();
        }
    }
    if (auto it = root.find("enforce_c1"); it != root.end()) {
        // joint indices must exist in every subpath they are applied to: the smallest joint count bounds them
        std::size_t joints = static_cast<std::size_t>(-1);
        for (const BezierChain& chain : chains) joints = std::min(joints, joint_count(chain));
        auto options = read_enforce(*it, joints);
        if (!options) return std::move(options.error());
        q.enforce = options.value();
    }
    if (auto it = root.find("evaluate"); it != root.end()) {
        std::size_t pieces = static_cast<std::size_t>(-1);
        for (const BezierChain& chain : chains) pieces = std::min(pieces, chain.pieces.size());
        const std::string what =
            svg && chains.size() > 1 ? "the parameter range of the shortest subpath" : "the chain's parameter range";
        auto ts = read_parameters_in(*it, "evaluate", 0.0, static_cast<double>(pieces), what);
        if (!ts) return std::move(ts.error());
        if (ts->size() * chains.size() > kMaxCurveQueries)
            return budget(std::to_string(ts->size() * chains.size()) + " parameters requested (" +
                              std::to_string(ts->size()) + " per subpath); the limit is " +
                              std::to_string(kMaxCurveQueries),
                          "evaluate");
        q.evaluate = std::move(ts.value());
    }
    if (auto it = root.find("length"); it != root.end()) {
        auto tolerance = read_tolerance(*it, "length");
        if (!tolerance) return std::move(tolerance.error());
        q.length = tolerance.value();
    }
    if (auto it = root.find("tessellate"); it != root.end()) {
        auto tolerance = read_tolerance(*it, "tessellate");
        if (!tolerance) return std::move(tolerance.error());
        q.tessellate = tolerance.value();
    }
    auto to_bezier = read_switch(root, "to_bezier");
    if (!to_bezier) return std::move(to_bezier.error());
    q.to_bezier = to_bezier.value();
    return q;
}

Json encode_continuity(const ContinuityReport& report) {
    Json joints = Json::array();
    for (const JointContinuity& j : report.joints)
        joints.push_back({{"left", j.left},
                          {"right", j.right},
                          {"continuity", to_string(j.continuity)},
                          {"gap", j.gap},
                          {"derivative_mismatch", j.derivative_mismatch},
                          {"angle", j.angle},
                          {"left_order", j.left_order},
                          {"right_order", j.right_order}});
    return {{"weakest", to_string(report.weakest)},
            {"max_gap", report.max_gap},
            {"max_derivative_mismatch", report.max_derivative_mismatch},
            {"max_angle", report.max_angle},
            {"joints", std::move(joints)}};
}

//! The chain queries on one chain; `polylines`, `segments` and `bound` collect the tessellation for glTF output.
struct ChainRun {
    const Limits& limits;
    const Cancel& cancel;
    const Encoder& encoder;
    std::size_t segments = 0;  //!< used so far, over all subpaths (the budget is for the whole request)
    double bound = 0;
    std::vector<Polyline> polylines;
};

ApiResult<Json> run_chain_queries(const BezierChain& input, const ChainQueries& q, ChainRun& run) {
    bool rational = false;
    for (const BezierCurve& piece : input.pieces) rational = rational || piece.is_rational();
    Json out = {{"piece_count", input.pieces.size()}, {"closed", input.closed}, {"rational", rational}};
    if (q.continuity) {
        auto report = continuity(input, *q.continuity);
        if (!report) return error_at(report.error(), "continuity");
        out["continuity"] = encode_continuity(*report);
    }
    const BezierChain* chain = &input;
    EnforceResult enforced;
    if (q.enforce) {
        auto result = enforce_c1(input, *q.enforce);
        if (!result) return error_at(result.error(), "enforce_c1");
        enforced = std::move(result.value());
        chain = &enforced.chain;
        out["enforce_c1"] = {{"chain", run.encoder.chain(enforced.chain)},
                             {"skipped_joints", enforced.skipped_joints},
                             {"max_derivative_mismatch", enforced.max_derivative_mismatch},
                             {"max_angle", enforced.max_angle}};
    }
    if (q.evaluate) {
        Json points = Json::array();
        for (double s : *q.evaluate) points.push_back(run.encoder.point(evaluate(*chain, s)));
        out["evaluate"] = std::move(points);
    }
    if (q.length) {
        // the tolerance is shared out over the pieces; gaps between pieces are not part of the length
        const double per_piece = std::max(*q.length / static_cast<double>(chain->pieces.size()), 1e-12);
        ArcLength total;
        for (const BezierCurve& piece : chain->pieces) {
            if (run.cancel.requested())
                return error_at(make_error(ErrorCode::Cancelled, "the request's deadline passed while measuring"),
                                "length");
            const ArcLength length = arc_length(piece, per_piece);
            total.length += length.length;
            total.error_bound += length.error_bound;
        }
        out["length"] = {{"length", total.length}, {"error_bound", total.error_bound}, {"guaranteed", !rational}};
    }
    if (q.tessellate) {
        ChainTessellationOptions options;
        options.tolerance = *q.tessellate;
        options.max_segments = static_cast<std::size_t>(run.limits.max_output_faces) - run.segments;
        options.cancel = run.cancel;
        auto polyline = tessellate(*chain, options);
        if (!polyline) return error_at(polyline.error(), "tessellate.tolerance");
        run.segments += polyline->segments;
        run.bound = std::max(run.bound, polyline->bound);
        out["tessellate"] = {{"points", run.encoder.points(polyline->points)}, {"params", polyline->params},
                             {"piece_start", polyline->piece_start},           {"segments", polyline->segments},
                             {"max_deviation", polyline->max_deviation},       {"bound", polyline->bound}};
        run.polylines.push_back(std::move(polyline->points));
    }
    if (q.to_bezier) out["to_bezier"] = run.encoder.chain(*chain);
    return out;
}

}  // namespace

ApiResponse run_chains(const Json& root, const ApiContext& context, OutputFormat format, bool svg) {
    if (svg) {
        if (auto error = check_form_members(
                root, "svg", "SVG path data",
                {"svg", "continuity", "enforce_c1", "evaluate", "length", "tessellate", "to_bezier", "output"}))
            return error_response(std::move(*error));
    } else if (auto error = check_form_members(
                   root, "chain", "a Bézier chain",
                   {"chain", "continuity", "enforce_c1", "evaluate", "length", "tessellate", "output"})) {
        return error_response(std::move(*error));
    }
    if (auto error = check_gltf_request(root, format, {"enforce_c1"})) return error_response(std::move(*error));

    Encoder encoder;
    std::vector<BezierChain> chains;
    if (svg) {
        auto decoded = decode_svg(root["svg"]);
        if (!decoded) return error_response(std::move(decoded.error()));
        chains = std::move(decoded.value());
        encoder.dimension = 2;
    } else {
        auto decoded = decode_chain(root["chain"], encoder.dimension);
        if (!decoded) return error_response(std::move(decoded.error()));
        chains.push_back(std::move(decoded.value()));
    }
    auto queries = read_chain_queries(root, chains, svg);
    if (!queries) return error_response(std::move(queries.error()));

    ChainRun run{context.limits, context.cancel, encoder, 0, 0.0, {}};
    Json results = Json::array();
    for (const BezierChain& chain : chains) {
        auto result = run_chain_queries(chain, queries.value(), run);
        if (!result) return error_response(std::move(result.error()));
        results.push_back(std::move(result.value()));
    }
    if (format != OutputFormat::Json) return polyline_response(run.polylines, format, run.segments, run.bound);
    if (svg) return json_response({{"subpaths", std::move(results)}});
    return json_response(results[0]);
}

}  // namespace surfaced::api::operations::curve_request
