// The mesh file commands: `surfaced subdivide`, `simplify`, `remesh` and `repair`, each the raw-file form of its
// POST endpoint, with the options of the endpoint's table (table_options.h).
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "server/cli/commands.h"
#include "server/cli/requests.h"
#include "server/cli/table_options.h"

namespace surfaced::cli {
namespace {

using api::options::OperationOptions;

constexpr std::string_view kSubdivideHelp = R"(Usage: surfaced subdivide IN -o OUT [options]

Subdivides the mesh in IN and writes it to OUT, through the same operation as POST /subdivide.
Formats come from the file extensions (or --input-format, --format):
  IN:  .obj .off .ply .stl .glb .gltf
  OUT: a --format name (.gltf is one JSON file with the data embedded; glTF is Draco-compressed unless
       --compression none; .json is {"mesh": ..., "stats": ...}); --format patches writes the limit surface as
       bicubic Bezier patches ({"patches": [...]}, what `surfaced tessellate` and POST /tessellate read), --levels
       then being the isolation level

)";

constexpr std::string_view kSimplifyHelp =
    R"(Usage: surfaced simplify IN -o OUT (--target-faces N | --ratio R | --max-error E) [options]

Simplifies the mesh in IN by quadric-error edge collapse and writes it to OUT, through the same operation as
POST /simplify. Polygons are triangulated first. Stops at whichever of the given criteria is reached first.
  IN:  .obj .off .ply .stl .glb .gltf  OUT: a --format name

)";

constexpr std::string_view kRemeshHelp =
    R"(Usage: surfaced remesh IN -o OUT [--edge-length L] [--iterations K] [options]

Remeshes the mesh in IN isotropically (split, collapse, flip, relax, project; Botsch-Kobbelt) towards edges of
length L and writes it to OUT, through the same operation as POST /remesh. Polygons are triangulated first. Sharp
edges and the boundary are kept. Prints the triangle quality before and after and the Hausdorff distance.
  IN:  .obj .off .ply .stl .glb .gltf  OUT: a --format name

)";

constexpr std::string_view kRepairHelp =
    R"(Usage: surfaced repair IN -o OUT [options]

Repairs the mesh in IN and writes it to OUT, through the same operation as POST /repair: welds vertices at the same
position, drops degenerate and duplicate faces, orients faces consistently (outward for closed parts), cuts
non-manifold edges and vertices apart, drops unreferenced vertices; optionally drops small components and fills small
holes. Prints what it did on stderr ("repaired IN: welded=...; ..."), the summary on stdout.
  IN:  .obj .off .ply .stl .glb .gltf  OUT: a --format name

)";

//! The options of a mesh command: its operation's table, --no-draco (deprecated: --compression none), and
//! --input-format.
std::vector<Option> mesh_options(const OperationOptions& operation) {
    std::vector<Option> options = table_options(operation, api::options::kQuery);
    options.push_back(deprecated_switch(operation, "--no-draco", "compression", "none"));
    options.push_back(Option{.name = "--input-format",
                             .check = one_of_names({"obj", "off", "ply", "stl", "glb", "gltf"}),
                             .synopsis = "--input-format NAME",
                             .description = "IN's format instead of its extension: obj off ply stl glb gltf (IN -: "
                                            "from its bytes)"});
    return options;
}

//! --max-output-faces: the output budget of a run (Limits::max_output_faces), a hand-written option.
Option max_output_faces_option() {
    return Option{.name = "--max-output-faces",
                  .check = integer(1, 4'000'000'000LL),
                  .synopsis = "--max-output-faces N",
                  .description = "refuse if the result would have more faces (default 4000000)"};
}

std::string help_of(std::string_view head, const OperationOptions& operation, const std::vector<Option>& options) {
    return std::string(head) + options_help(operation, options);
}

}  // namespace

int subdivide(Args& args) {
    api::ApiContext context = file_context();
    const OperationOptions& operation = *api::options::operation_options("subdivide");
    std::vector<Option> options = mesh_options(operation);
    options.push_back(max_output_faces_option());
    const auto parsed = parse_file_command(args, "subdivide", help_of(kSubdivideHelp, operation, options), options);
    if (!parsed) return kExitOk;
    const std::optional<MeshFormat> in_format = mesh_input_format(*parsed);
    if (parsed->has("--max-output-faces"))
        context.limits.max_output_faces = std::stoull(parsed->value("--max-output-faces"));
    if (parsed->has("--format") && parsed->value("--format") == "patches") {
        // the limit surface as Bézier patches: JSON, whatever OUT's extension
        const auto bytes = read_input(parsed->input);
        if (!bytes) return kExitFailed;
        std::multimap<std::string, std::string> query(parsed->params.begin(), parsed->params.end());
        query.emplace("format", "patches");
        const MeshFormat format = in_format ? *in_format : sniff_mesh_format(*bytes);
        const api::ApiRequest request = upload_request(
            "/subdivide", std::string(api::enum_name(api::kMeshMediaTypes, format)), *bytes, std::move(query));
        return finish(api::dispatch(request, context), *parsed, [&](const api::ApiResponse& response) {
            parsed->report() << "wrote " << parsed->output_label() << ": " << header(response, "X-Patches")
                             << " patches at isolation level " << header(response, "X-Isolation-Level") << " ("
                             << header(response, "X-Approximate-Patches") << " approximate, max error "
                             << header(response, "X-Max-Error") << ") in " << header(response, "X-Elapsed-Ms")
                             << " ms\n";
        });
    }
    const api::OutputFormat out_format = output_format(*parsed, operation);

    return upload_mesh("/subdivide", *parsed, in_format, out_format, context, [&](const api::ApiResponse& response) {
        parsed->report() << "wrote " << parsed->output_label() << ": " << header(response, "X-Output-Vertices")
                         << " vertices, " << header(response, "X-Output-Faces") << " faces (from "
                         << header(response, "X-Input-Vertices") << " vertices, " << header(response, "X-Input-Faces")
                         << " faces) in " << header(response, "X-Elapsed-Ms") << " ms\n";
    });
}

int simplify(Args& args) {
    api::ApiContext context = file_context();
    const OperationOptions& operation = *api::options::operation_options("simplify");
    const std::vector<Option> options = mesh_options(operation);
    const auto parsed = parse_file_command(args, "simplify", help_of(kSimplifyHelp, operation, options), options);
    if (!parsed) return kExitOk;
    if (!parsed->param("target_faces") && !parsed->param("ratio") && !parsed->param("max_error"))
        throw UsageError{"simplify: give --target-faces, --ratio or --max-error"};
    const std::optional<MeshFormat> in_format = mesh_input_format(*parsed);
    const api::OutputFormat out_format = output_format(*parsed, operation);

    return upload_mesh("/simplify", *parsed, in_format, out_format, context, [&](const api::ApiResponse& response) {
        print_repairs(*parsed, response);
        print_triangulated_result(*parsed, response);
        parsed->report() << ", error " << header(response, "X-Achieved-Error") << " ("
                         << header(response, "X-Relative-Error") << " of the bounding-box diagonal)";
        if (parsed->param("report_error") == "true")
            parsed->report() << ", Hausdorff " << header(response, "X-Hausdorff") << ", RMS "
                             << header(response, "X-RMS");
        parsed->report() << ", in " << header(response, "X-Elapsed-Ms") << " ms\n";
    });
}

int remesh(Args& args) {
    api::ApiContext context = file_context();
    const OperationOptions& operation = *api::options::operation_options("remesh");
    std::vector<Option> options = mesh_options(operation);
    // the boundary option by its name when it was introduced, so that a rename in the table keeps this spelling
    options.push_back(deprecated_switch(operation, "--free-boundary", "keep_boundary", "false"));
    const auto parsed = parse_file_command(args, "remesh", help_of(kRemeshHelp, operation, options), options);
    if (!parsed) return kExitOk;
    const std::optional<MeshFormat> in_format = mesh_input_format(*parsed);
    const api::OutputFormat out_format = output_format(*parsed, operation);

    return upload_mesh("/remesh", *parsed, in_format, out_format, context, [&](const api::ApiResponse& response) {
        print_repairs(*parsed, response);
        print_triangulated_result(*parsed, response);
        parsed->report() << ", edge length " << header(response, "X-Edge-Length") << " (mean "
                         << header(response, "X-Mean-Edge-Length-After") << "), min angle "
                         << header(response, "X-Min-Angle-Before") << " -> " << header(response, "X-Min-Angle-After")
                         << " deg, below 30 deg " << header(response, "X-Below-30-Before") << " -> "
                         << header(response, "X-Below-30-After") << ", radius ratio "
                         << header(response, "X-Radius-Ratio-Before") << " -> "
                         << header(response, "X-Radius-Ratio-After") << ", Hausdorff "
                         << header(response, "X-Hausdorff") << ", in " << header(response, "X-Elapsed-Ms") << " ms\n";
    });
}

int repair(Args& args) {
    api::ApiContext context = file_context();
    const OperationOptions& operation = *api::options::operation_options("repair");
    const std::vector<Option> options = mesh_options(operation);
    const auto parsed = parse_file_command(args, "repair", help_of(kRepairHelp, operation, options), options);
    if (!parsed) return kExitOk;
    const std::optional<MeshFormat> in_format = mesh_input_format(*parsed);
    const api::OutputFormat out_format = output_format(*parsed, operation);

    return upload_mesh("/repair", *parsed, in_format, out_format, context, [&](const api::ApiResponse& response) {
        print_repairs(*parsed, response, true);
        parsed->report() << "wrote " << parsed->output_label() << ": " << header(response, "X-Output-Faces")
                         << " faces, " << header(response, "X-Output-Vertices") << " vertices (from "
                         << header(response, "X-Input-Faces") << " faces, " << header(response, "X-Input-Vertices")
                         << " vertices), in " << header(response, "X-Elapsed-Ms") << " ms\n";
    });
}

}  // namespace surfaced::cli
