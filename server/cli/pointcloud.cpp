// `surfaced pointcloud`: a point file converted through POST /pointcloud, optionally with estimated normals.
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/io/pointcloud_io.h"
#include "server/cli/commands.h"
#include "server/cli/point_input.h"
#include "server/cli/requests.h"
#include "server/cli/table_options.h"

namespace surfaced::cli {
namespace {

constexpr std::string_view kPointcloudHelp =
    R"(Usage: surfaced pointcloud IN -o OUT [--estimate-normals [--k N]] [options]

Reads the points in IN and writes them to OUT, through the same operation as POST /pointcloud; with
--estimate-normals the normals are replaced by PCA of the k nearest neighbours, consistently oriented (outward on
closed shapes).
  IN:  .ply .obj .xyz (.txt .pts as XYZ) .glb .gltf (POINTS, else the mesh vertices)
  OUT: a --format name (.glb: Draco POINTS unless --compression none)

)";

}  // namespace

int pointcloud(Args& args) {
    api::ApiContext context = file_context();
    const api::options::OperationOptions& operation = *api::options::operation_options("pointcloud");
    std::vector<Option> options = table_options(operation, api::options::kQuery);
    options.push_back(deprecated_switch(operation, "--no-draco", "compression", "none"));
    options.push_back(point_input_format_option());
    const auto parsed = parse_file_command(args, "pointcloud",
                                           std::string(kPointcloudHelp) + options_help(operation, options), options);
    if (!parsed) return kExitOk;
    std::optional<PointFormat> in_format = point_input_format(*parsed);
    const api::OutputFormat out_format = output_format(*parsed, operation);

    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    if (!in_format)  // standard input: glTF or PLY magic, OBJ vertex lines, else XYZ
        in_format = sniff_point_format(*bytes).value_or(PointFormat::Xyz);
    const std::string content_type(point_media_type(*in_format));
    const api::ApiRequest request =
        upload_request("/pointcloud", content_type, *bytes, file_query(*parsed, out_format));
    return finish(api::dispatch(request, context), *parsed, [&](const api::ApiResponse& response) {
        parsed->report() << "wrote " << parsed->output_label() << ": " << header(response, "X-Output-Points")
                         << " points" << (header(response, "X-Normals") == "true" ? ", normals" : "")
                         << (header(response, "X-Colors") == "true" ? ", colors" : "") << ", in "
                         << header(response, "X-Elapsed-Ms") << " ms\n";
    });
}

}  // namespace surfaced::cli
