// The patch, surface and curve file commands: `surfaced tessellate` (POST /tessellate, GET /patches/NAME),
// `surfaced surfaces` (POST /surfaces) and `surfaced curve` (POST /curves).
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/operations/curves.h"
#include "server/cli/commands.h"
#include "server/cli/requests.h"
#include "server/cli/table_options.h"

namespace surfaced::cli {
namespace {

using api::options::OperationOptions;

constexpr std::string_view kTessellateHelp =
    R"(Usage: surfaced tessellate IN -o OUT (--tolerance T | --segments N) [options]

Tessellates the Bezier patches in IN (a geomview .bez/.bbp file, an .obj with cstype [rat] bezier or [rat] bspline
surfaces, a .json {"patches": [...]} as POST /tessellate takes it, e.g. from `surfaced subdivide --format patches`,
or sample:teapot for a built-in sample) into a crack-free triangle mesh with normals and UVs, through the same
operation as POST /tessellate (GET /patches/NAME). OUT: a --format name (.glb is Draco-compressed unless
--compression none). Trimmed surfaces (a .json surface with "trim", an .obj surf with trim/hole statements over
curv2 curves) need --tolerance.

)";

constexpr std::string_view kSurfacesHelp =
    R"(Usage: surfaced surfaces IN.json -o OUT.json

Runs queries on the B-spline/NURBS surface in IN, a POST /surfaces body ({"surface": {...}, "evaluate": [[u, v]],
"closest": [[x, y, z]], "elevate": {"direction": "u"}, ...}), through the same operation, and writes its JSON answer
to OUT.

Options:
  -o, --output OUT       output file (required); - for standard output
  -h, --help             this text
)";

constexpr std::string_view kCurveHelp =
    R"(Usage: surfaced curve IN.json|IN.svg -o OUT [--tolerance T] [--continuity] [--enforce-c1 MODE]

Runs curve queries on the curve in IN and writes the answer to OUT, through the same operation as POST /curves.
  IN:  .json  a POST /curves body: one of "points", "chain", "svg", "bspline", and its queries
       .svg   the d attributes of the <path> elements (one chain per subpath; transforms are not applied),
              or a file of bare path data
  OUT: .json (the answer) .glb .gltf (the tessellation as glTF line strips; no Draco, which is for triangles)

Options:
  -o, --output OUT       output file (required); - for standard output
  --format F             output format instead of OUT's extension: json glb gltf (needed with -o -)
  --input-format F       IN's format instead of its extension: json svg (IN -: json if it starts with {)
  --tolerance T          tessellate within T model units (.glb/.gltf: default the file's, else 0.001)
  --continuity           report every joint: gap, derivative mismatch, angle, class (chains, SVG paths)
  --enforce-c1 MODE      make every joint C1 or G1 (MODE: C1, G1) by the mirror rule (chains, SVG paths);
                         the answer has the modified chain, and the tessellation is of it
  -h, --help             this text
)";

//! The POST /tessellate JSON body of a {"patches": [...]} file with the command's options laid over it ("output" is
//! the command's, format from OUT). A file that is not a JSON object goes to the operation unchanged, which reports
//! where it breaks.
std::string patches_request_body(const std::string& bytes, const Parsed& parsed, const OperationOptions& operation,
                                 api::OutputFormat format) {
    nlohmann::json doc = nlohmann::json::parse(bytes, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return bytes;
    doc["output"] = {{"format", std::string(api::enum_name(api::kOutputFormatNames, format))}};
    for (const auto& [name, text] : parsed.params) {
        const api::options::OptionSpec& spec = table_option(operation, name);
        nlohmann::json& container = spec.json_object.empty() ? doc : doc[std::string(spec.json_object)];
        container[name] = option_json_value(spec, text);
    }
    return doc.dump();
}

}  // namespace

int tessellate(Args& args) {
    api::ApiContext context = file_context();
    const OperationOptions& operation = *api::options::operation_options("tessellate");
    std::vector<Option> options = table_options(operation, api::options::kQuery);
    options.push_back(deprecated_switch(operation, "--no-draco", "compression", "none"));
    options.push_back(Option{.name = "--input-format",
                             .check = one_of_names({"bez", "obj", "json"}),
                             .synopsis = "--input-format NAME",
                             .description = "IN's format instead of its extension: bez obj json (IN -: json if it "
                                            "starts with {, obj if it has cstype lines)"});
    options.push_back(Option{.name = "--max-output-faces",
                             .check = integer(1, 4'000'000'000LL),
                             .synopsis = "--max-output-faces N",
                             .description = "refuse if the result could have more triangles (default 4000000)"});
    const auto parsed = parse_file_command(args, "tessellate",
                                           std::string(kTessellateHelp) + options_help(operation, options), options);
    if (!parsed) return kExitOk;
    if (parsed->param("tolerance") && parsed->param("segments"))
        throw UsageError{"tessellate: give --tolerance or --segments, not both"};
    const api::OutputFormat format = output_format(*parsed, operation);
    if (parsed->has("--max-output-faces"))
        context.limits.max_output_faces = std::stoull(parsed->value("--max-output-faces"));

    // The request POST /tessellate (or GET /patches/NAME) would receive: one code path for CLI and service.
    std::optional<std::string> bytes, json_body;
    api::ApiRequest request;
    if (parsed->input.starts_with("sample:")) {
        request.method = "GET";
        request.path = "/patches/" + parsed->input.substr(7);
        request.query = file_query(*parsed, format);
    } else {
        bytes = read_input(parsed->input);
        if (!bytes) return kExitFailed;
        // free-form bezier or bspline surfaces in an OBJ; from standard input, an OBJ is known by its cstype lines and
        // JSON by its opening brace
        const std::string kind = parsed->has("--input-format") ? parsed->value("--input-format")
                                 : parsed->from_stdin() ? (bytes->find_first_not_of(" \t\r\n") != std::string::npos &&
                                                                   (*bytes)[bytes->find_first_not_of(" \t\r\n")] == '{'
                                                               ? "json"
                                                           : bytes->find("cstype") != std::string::npos ? "obj"
                                                                                                        : "bez")
                                                        : std::string(lower_extension(parsed->input)).erase(0, 1);
        if (kind == "json") {
            // the JSON body form: the file's patches with the command's options laid over it
            json_body = patches_request_body(*bytes, *parsed, operation, format);
            request = upload_request("/tessellate", "application/json", *json_body, {});
        } else {
            request = upload_request("/tessellate", kind == "obj" ? "model/obj" : "application/x-geomview-bez", *bytes,
                                     file_query(*parsed, format));
        }
    }
    return finish(
        api::dispatch(request, context), *parsed,
        [&](const api::ApiResponse& response) {
            parsed->report() << "wrote " << parsed->output_label() << ": " << header(response, "X-Output-Vertices")
                             << " vertices, " << header(response, "X-Output-Faces") << " triangles from "
                             << header(response, "X-Patches")
                             << " patches, max deviation <= " << header(response, "X-Error-Bound") << ", in "
                             << header(response, "X-Elapsed-Ms") << " ms\n";
        },
        ProblemStyle{.line = true, .offset = false});
}

int surfaces(Args& args) {
    api::ApiContext context = file_context();
    const auto parsed = parse_file_command(args, "surfaces", kSurfacesHelp, {}, "IN.json");
    if (!parsed) return kExitOk;
    if (parsed->has("--format")) throw UsageError{"surfaces: the answer is JSON; --format does not apply"};
    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    return finish(
        api::dispatch(upload_request("/surfaces", "application/json", *bytes, {}), context), *parsed,
        [&](const api::ApiResponse&) { parsed->report() << "wrote " << parsed->output_label() << "\n"; },
        ProblemStyle{.field = true, .line = true, .offset = true});
}

int curve(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--tolerance", "", real()},
        flag("--continuity"),
        {"--enforce-c1", "", one_of_names({"C1", "G1"})},
        {"--input-format", "", one_of_names({"json", "svg"})},
    };
    const auto parsed = parse_file_command(args, "curve", kCurveHelp, options, "IN.json or IN.svg");
    if (!parsed) return kExitOk;
    // .json or .svg: --input-format, else the extension; from standard input a JSON object starts with '{'
    std::optional<bool> svg;
    if (parsed->has("--input-format"))
        svg = parsed->value("--input-format") == "svg";
    else if (!parsed->from_stdin()) {
        const std::string in_ext = lower_extension(parsed->input);
        if (in_ext != ".json" && in_ext != ".svg")
            throw UsageError{"cannot tell the curve format of " + parsed->input +
                             " from its extension (use .json .svg, or --input-format)"};
        svg = in_ext == ".svg";
    }
    using enum api::OutputFormat;
    const api::OutputFormat out_format = output_format(*parsed, *api::options::operation_options("curves"));
    api::operations::CurveFileOverrides overrides;
    overrides.format = out_format;
    if (parsed->has("--tolerance")) overrides.tolerance = std::stod(parsed->value("--tolerance"));
    overrides.continuity = parsed->has("--continuity");
    if (parsed->has("--enforce-c1")) overrides.enforce_c1 = parsed->value("--enforce-c1");

    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    if (!svg) {
        const std::size_t first = bytes->find_first_not_of(" \t\r\n");
        svg = first == std::string::npos || (*bytes)[first] != '{';
    }
    overrides.svg = *svg;
    return finish(
        api::operations::curves_from_file(*bytes, overrides, context), *parsed,
        [&](const api::ApiResponse& response) {
            parsed->report() << "wrote " << parsed->output_label();
            if (out_format != Json)
                parsed->report() << ": " << header(response, "X-Polylines") << " line strip(s), "
                                 << header(response, "X-Segments") << " segments within "
                                 << header(response, "X-Error-Bound") << " of the curve";
            parsed->report() << "\n";
        },
        ProblemStyle{.field = true, .line = true, .offset = true});
}

}  // namespace surfaced::cli
