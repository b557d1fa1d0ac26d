// `surfaced reconstruct`: a closed surface from a point file, through POST /reconstruct.
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/io/pointcloud_io.h"
#include "server/cli/commands.h"
#include "server/cli/limit_flags.h"
#include "server/cli/point_input.h"
#include "server/cli/requests.h"
#include "server/cli/table_options.h"

namespace surfaced::cli {
namespace {

constexpr std::string_view kReconstructHelp =
    R"(Usage: surfaced reconstruct IN -o OUT [--depth N] [--point-weight W] [options]

Reconstructs the closed surface the points in IN sample (screened Poisson reconstruction), through the same
operation as POST /reconstruct. Points without normals get normals estimated from their k nearest neighbours and
oriented consistently (outward on closed shapes) first, unless --estimate-normals never.
  IN:  .ply .obj .xyz (.txt .pts as XYZ) .glb .gltf (POINTS, else the mesh vertices)
  OUT: a mesh format by extension or --format (.glb: Draco; vertex colours in .glb .ply .obj .json)
Depth 8 has a 256^3 finest grid (meshed where the surface crosses it: about a second and 150 MB for 50,000
points); each level more is 8x the grid, so depths 9 and 10 need --max-grid-cells (and, for large clouds,
--max-reconstruct-bytes) raised: the reconstruction of 1,000,000 points at depth 10 takes 2-3 GB and 13-20 s
with --threads 2 on two cores.

)";

}  // namespace

int reconstruct(Args& args) {
    api::ApiContext context = file_context();
    const api::options::OperationOptions& operation = *api::options::operation_options("reconstruct");
    std::vector<Option> options = table_options(operation, api::options::kQuery);
    options.push_back(deprecated_switch(operation, "--no-draco", "compression", "none"));
    options.push_back(point_input_format_option());
    // the budgets a large reconstruction meets, as `surfaced serve` takes them
    constexpr std::string_view kBudgets[] = {"--max-grid-cells", "--max-reconstruct-bytes", "--max-points"};
    for (const std::string_view flag : kBudgets) options.push_back(limit_option(flag));
    const auto parsed = parse_file_command(args, "reconstruct",
                                           std::string(kReconstructHelp) + options_help(operation, options), options);
    if (!parsed) return kExitOk;
    for (const std::string_view flag : kBudgets)
        if (parsed->has(flag)) apply_limit_flag(flag, parsed->value(flag), context.limits);
    std::optional<PointFormat> in_format = point_input_format(*parsed);
    const api::OutputFormat out_format = output_format(*parsed, operation);

    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    // standard input without --input-format: the service sniffs the bytes (application/octet-stream)
    const std::string content_type = in_format ? std::string(point_media_type(*in_format)) : "application/octet-stream";
    const api::ApiRequest request =
        upload_request("/reconstruct", content_type, *bytes, file_query(*parsed, out_format));
    return finish(api::dispatch(request, context), *parsed, [&](const api::ApiResponse& response) {
        parsed->report() << "wrote " << parsed->output_label() << ": " << header(response, "X-Output-Vertices")
                         << " vertices, " << header(response, "X-Output-Faces") << " triangles from "
                         << header(response, "X-Input-Points") << " points (depth " << header(response, "X-Depth")
                         << (header(response, "X-Normals-Estimated") == "true" ? ", normals estimated" : "")
                         << (header(response, "X-Colors") == "true" ? ", colours" : "") << "), in "
                         << header(response, "X-Elapsed-Ms") << " ms\n";
    });
}

}  // namespace surfaced::cli
