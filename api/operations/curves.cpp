// POST /curves (see curves.h): the request's members, its form and output format, then the form's operation
// (curves_bezier.cpp, curves_chains.cpp, curves_bspline.cpp, sharing curve_request.h), and the command line's files.
// Decoding and encoding live together in these translation units because the response mirrors the request's
// members. Order for every form: the request's shape (members, form, output), then the curve, then every query's
// options and the budgets, and only then any work.
#include "api/operations/curves.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <initializer_list>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "api/json_util.h"
#include "api/operations/curve_request.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"

#include "geometry/curves/bezier_curve.h"
#include "geometry/curves/bspline.h"
#include "geometry/curves/piecewise.h"
#include "geometry/curves/svg_path.h"
#include "geometry/io/polyline_gltf.h"

namespace surfaced::api::operations {
namespace {

using namespace json;
using namespace curve_request;

//! "output": {"format": "json" | "glb" | "gltf", "compression": "none"} by the option table; when the body names no
//! format, the one the Accept header prefers (json on a tie or without Accept; 406 when Accept takes none of them).
ApiResult<OutputFormat> read_output(const Json& root, const ApiRequest& request) {
    auto values = options::read_json(*options::operation_options("curves"), root);
    if (!values) return std::move(values.error());
    OutputOptions output;
    output.format = OutputFormat::Json;
    output.format_given = values->has("format");
    values->get("format", kOutputFormatNames, output.format);
    if (auto error = negotiate_output_format(request, output)) return std::move(*error);
    const OutputFormat format = output.format;
    if (values->has("compression") && format == OutputFormat::Json)
        return invalid("output.compression", "output.compression applies to glb/gltf output only");
    return format;
}

// ---- the request -------------------------------------------------------------------------------------------------

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    if (auto error = check_json_only_body(request, limits, "POST /curves")) return error_response(std::move(*error));
    Json root;
    if (auto error = json::parse(request.body, root)) return error_response(std::move(*error));
    if (!root.is_object()) return error_response(invalid("", "the body must be a JSON object"));
    static constexpr std::string_view kMembers[] = {
        "points",       "weights",    "evaluate",  "derivatives", "curvature", "split", "elevate",
        "bounding_box", "length",     "closest",   "tessellate",  "chain",     "svg",   "bspline",
        "continuity",   "enforce_c1", "to_bezier", "insert_knot", "output"};
    for (const auto& item : root.items())
        if (std::find(std::begin(kMembers), std::end(kMembers), item.key()) == std::end(kMembers))
            return error_response(
                make_problem(Problem::UnknownField, "unknown field \"" + item.key() + "\" at top level", item.key()));

    // the form: exactly one of them
    static constexpr const char* kForms[] = {"points", "chain", "svg", "bspline"};
    std::vector<std::string> forms;
    for (const char* form : kForms)
        if (root.contains(form)) forms.emplace_back(form);
    if (forms.size() > 1)
        return error_response(invalid(forms[1], "give exactly one curve: \"" + forms[0] + "\" and \"" + forms[1] +
                                                    "\" were both given (forms: points, chain, svg, bspline)"));
    if (forms.empty())
        return error_response(invalid("points",
                                      "a curve is required: \"points\" (one Bézier curve: [[x, y], ...] or "
                                      "[[x, y, z], ...]), \"chain\", \"svg\" or \"bspline\""));
    auto format = read_output(root, request);
    if (!format) return error_response(std::move(format.error()));

    if (forms[0] == "points") return run_single(root, limits, format.value());
    if (forms[0] == "bspline") return run_bspline(root, context, format.value());
    return run_chains(root, context, format.value(), forms[0] == "svg");
}

// ---- files (the CLI) ---------------------------------------------------------------------------------------------

//! The path data of an SVG file: every <path> element's d attribute, joined by spaces (each starts with a move), or
//! the whole file when it is bare path data. `starts` maps each joined piece back to its offset in the file.
struct SvgText {
    std::string data;
    std::vector<std::pair<std::size_t, std::size_t>> starts;  //!< (offset in data, offset in file)
};

SvgText extract_svg_paths(std::string_view file) {
    SvgText out;
    const std::size_t first = file.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos || file[first] != '<') {
        out.data = std::string(file);
        out.starts.push_back({0, 0});
        return out;
    }
    std::size_t pos = 0;
    while ((pos = file.find("<path", pos)) != std::string_view::npos) {
        const std::size_t end = file.find('>', pos);
        if (end == std::string_view::npos) break;
        const std::string_view element = file.substr(pos, end - pos);
        // the attribute " d=" (not "id=" or "data-d="): preceded by whitespace
        for (std::size_t a = element.find("d="); a != std::string_view::npos; a = element.find("d=", a + 1)) {
            if (a == 0 ||
                (element[a - 1] != ' ' && element[a - 1] != '\t' && element[a - 1] != '\n' && element[a - 1] != '\r'))
                continue;
            if (a + 2 >= element.size() || (element[a + 2] != '"' && element[a + 2] != '\'')) continue;
            const char quote = element[a + 2];
            const std::size_t value = a + 3, close = element.find(quote, value);
            if (close == std::string_view::npos) break;
            if (!out.data.empty()) out.data += ' ';
            out.starts.push_back({out.data.size(), pos + value});
            out.data += element.substr(value, close - value);
            break;
        }
        pos = end;
    }
    return out;
}

ApiResponse run_from_file(std::string_view file, const CurveFileOverrides& overrides, const ApiContext& context) {
    Json root;
    SvgText svg;
    if (overrides.svg) {
        svg = extract_svg_paths(file);
        if (svg.data.find_first_not_of(" \t\r\n") == std::string::npos)
            return error_response(invalid("svg", "the file has no SVG path data (no <path d=\"...\"> element)"));
        root = Json::object();
        root["svg"] = svg.data;
    } else {
        if (auto error = json::parse(file, root)) return error_response(std::move(*error));
        if (!root.is_object())
            return error_response(invalid("", "the file must hold a JSON object (a POST /curves request)"));
    }
    if (overrides.tolerance) root["tessellate"] = {{"tolerance", *overrides.tolerance}};
    if (overrides.continuity) root["continuity"] = true;
    if (overrides.enforce_c1) root["enforce_c1"] = {{"mode", *overrides.enforce_c1}};
    root.erase("output");
    if (overrides.format != OutputFormat::Json) {
        root["output"] = {{"format", std::string(enum_name(kOutputFormatNames, overrides.format))}};
        if (!root.contains("tessellate")) root["tessellate"] = {{"tolerance", kDefaultCurveFileTolerance}};
    }
    // invalid UTF-8 in an SVG file is replaced (the path parser then reports the first such byte)
    const std::string body = json_text(root);
    ApiRequest request;
    request.method = "POST";
    request.path = "/curves";
    request.content_type = "application/json";
    request.body = body;
    ApiResponse response = run(request, context);
    // an SVG error's offset is in the path data: translate it to the file (and a line there)
    if (overrides.svg && response.error && response.error->field == "svg" && response.error->offset) {
        const auto offset = static_cast<std::size_t>(*response.error->offset);
        std::size_t file_offset = offset;
        for (const auto& [data_start, file_start] : svg.starts)
            if (data_start <= offset) file_offset = file_start + (offset - data_start);
        file_offset = std::min(file_offset, file.size());
        response.error->offset = static_cast<std::int64_t>(file_offset);
        response.error->line = static_cast<std::int64_t>(
            1 + std::count(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(file_offset), '\n'));
        response.body = to_problem_json(*response.error);
    }
    return response;
}

}  // namespace

ApiResponse curves(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

ApiResponse curves_from_file(std::string_view file, const CurveFileOverrides& overrides,
                             const ApiContext& context) noexcept {
    return guarded([&] { return run_from_file(file, overrides, context); });
}

}  // namespace surfaced::api::operations
