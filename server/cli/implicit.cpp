// `surfaced implicit`: a scene file meshed through POST /implicit/mesh, with the command's options (the operation's
// table, table_options.h) laid over it.
#include <iostream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/cli/commands.h"
#include "server/cli/limit_flags.h"
#include "server/cli/requests.h"
#include "server/cli/table_options.h"

namespace surfaced::cli {
namespace {

constexpr std::string_view kImplicitHelp =
    R"(Usage: surfaced implicit SCENE.json -o OUT [--bounds B] [--resolution N | --cell-size H] [options]

Meshes the zero level set of an implicit scene inside its bounds, through the same operation as POST /implicit/mesh
(dual marching cubes with QEF vertices: closed, manifold, consistently oriented, sharp edges kept). Where the
surface meets the bounds it is closed by flat caps. SCENE.json (- for standard input) is a request body:
  {"scene": {"op": "difference", "args": [...]}, "bounds": [[x0,y0,z0],[x1,y1,z1]], "resolution": 64}
or the scene alone, {"op": "difference", "args": [...]}, with --bounds. The options below replace the file's
members (--resolution and --cell-size both of its grid members); the defaults are those of a body without them.
OUT: a --format name; the output options of the file are replaced by those given here.

)";

//! --bounds: six numbers, the minimum corner then the maximum one (the operation checks that min < max).
std::string checked_bounds(std::string_view option, const std::string& text) {
    std::vector<std::string> numbers;
    std::istringstream in(text);
    for (std::string number; std::getline(in, number, ',');) numbers.push_back(checked_real(option, number));
    if (numbers.size() != 6 || text.ends_with(","))
        throw UsageError{std::string(option) + " needs six numbers xmin,ymin,zmin,xmax,ymax,zmax, got \"" + text +
                         "\""};
    return text;
}

//! The POST /implicit/mesh body of SCENE.json with the command's options laid over it: a request body, or a scene
//! alone (an object with "op" and no "scene") as the request's "scene"; --bounds replaces the file's bounds or gives
//! a bare scene its own; --resolution and --cell-size replace both grid members; "output" is the command's (format
//! from OUT). A file that is not a JSON object goes to the operation unchanged, which reports where it breaks.
std::string implicit_request_body(const std::string& bytes, const Parsed& parsed,
                                  const api::options::OperationOptions& operation, api::OutputFormat format) {
    nlohmann::json doc = nlohmann::json::parse(bytes, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return bytes;
    if (!doc.contains("scene") && doc.contains("op")) {
        if (!parsed.has("--bounds"))
            throw UsageError{"implicit: " + parsed.input_label() +
                             " is a scene alone (no \"scene\" member): give --bounds xmin,ymin,zmin,xmax,ymax,zmax"};
        doc = nlohmann::json{{"scene", std::move(doc)}};
    }
    if (parsed.has("--bounds")) {
        std::vector<double> v;
        std::istringstream in(parsed.value("--bounds"));
        for (std::string number; std::getline(in, number, ',');) v.push_back(std::stod(number));
        doc["bounds"] = nlohmann::json::array({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}});
    }
    if (parsed.param("resolution") || parsed.param("cell_size")) {
        doc.erase("resolution");
        doc.erase("cell_size");
    }
    doc["output"] = {{"format", std::string(api::enum_name(api::kOutputFormatNames, format))}};
    for (const auto& [name, text] : parsed.params) {
        const api::options::OptionSpec& spec = table_option(operation, name);
        nlohmann::json& container = spec.json_object.empty() ? doc : doc[std::string(spec.json_object)];
        container[name] = option_json_value(spec, text);
    }
    return doc.dump();
}

}  // namespace

int implicit(Args& args) {
    api::ApiContext context = file_context();
    const api::options::OperationOptions& operation = *api::options::operation_options("implicit_mesh");
    std::vector<Option> options = table_options(operation, api::options::kJson);
    options.push_back(deprecated_switch(operation, "--no-draco", "compression", "none"));
    options.push_back(Option{.name = "--bounds",
                             .check = checked_bounds,
                             .synopsis = "--bounds X0,Y0,Z0,X1,Y1,Z1",
                             .description = "the box to mesh in (default: the file's; required for a scene alone)"});
    options.push_back(limit_option("--max-grid-cells"));
    const auto parsed = parse_file_command(
        args, "implicit", std::string(kImplicitHelp) + options_help(operation, options), options, "SCENE.json");
    if (!parsed) return kExitOk;
    if (parsed->param("resolution") && parsed->param("cell_size"))
        throw UsageError{"implicit: give --resolution or --cell-size, not both"};
    const api::OutputFormat out_format = output_format(*parsed, operation);
    if (parsed->has("--max-grid-cells"))
        apply_limit_flag("--max-grid-cells", parsed->value("--max-grid-cells"), context.limits);

    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    const std::string body = implicit_request_body(*bytes, *parsed, operation, out_format);
    return finish(
        api::dispatch(upload_request("/implicit/mesh", "application/json", body, {}), context), *parsed,
        [&](const api::ApiResponse& response) {
            parsed->report() << "wrote " << parsed->output_label() << ": " << header(response, "X-Output-Faces")
                             << " triangles, " << header(response, "X-Output-Vertices") << " vertices, grid "
                             << header(response, "X-Grid") << " (" << header(response, "X-Surface-Cells")
                             << " surface cells, " << header(response, "X-Field-Evaluations")
                             << " field evaluations), in " << header(response, "X-Elapsed-Ms") << " ms\n";
        },
        ProblemStyle{.field = true, .line = false, .offset = true});
}

}  // namespace surfaced::cli
