// `surfaced pointcloud`: a point file converted through POST /pointcloud, optionally with estimated normals.
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/io/pointcloud_io.h"
#include "server/cli/commands.h"
#include "server/cli/requests.h"

namespace surfaced::cli {
namespace {

constexpr std::string_view kPointcloudHelp =
    R"(Usage: surfaced pointcloud IN -o OUT [--estimate-normals [--k N]] [options]

Reads the points in IN and writes them to OUT, through the same operation as POST /pointcloud; with
--estimate-normals the normals are replaced by PCA of the k nearest neighbours, consistently oriented (outward on
closed shapes).
  IN:  .ply .obj .xyz (.txt .pts as XYZ)        OUT: .glb (Draco POINTS) .ply .json

Options:
  -o, --output OUT          output file (required); - for standard output
  --format F                output format instead of OUT's extension: glb ply json (needed with -o -)
  --input-format F          IN's format instead of its extension: ply obj xyz (IN -: from the bytes)
  --estimate-normals        estimate and orient normals
  --k N                     neighbours for --estimate-normals, 3..256 (default 16)
  --no-normals              leave normals out of the output
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb only)
  -h, --help                this text
)";

}  // namespace

int pointcloud(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        flag("--estimate-normals", "estimate_normals"),
        {"--k", "k", integer(3, 256)},
        flag("--no-normals", "normals", "false"),
        flag("--no-draco"),
        {"--quantize-position", "quantize_position", integer(1, 24)},
        {"--input-format", "", one_of_names({"ply", "obj", "xyz"})},
    };
    const auto parsed = parse_file_command(args, "pointcloud", kPointcloudHelp, options);
    if (!parsed) return kExitOk;
    if (parsed->has("--k") && !parsed->has("--estimate-normals"))
        throw UsageError{"--k applies only with --estimate-normals"};
    std::optional<PointFormat> in_format;
    if (parsed->has("--input-format"))
        in_format = point_format_from_extension("." + parsed->value("--input-format"));
    else if (!parsed->from_stdin() && !(in_format = point_format_from_extension(parsed->input)))
        throw UsageError{"cannot tell the point format of " + parsed->input +
                         " from its extension (use .ply .obj .xyz, or --input-format)"};
    using enum api::OutputFormat;
    const api::OutputFormat out_format = output_format(*parsed, {Glb, Ply, Json});
    const bool no_draco = parsed->has("--no-draco"), quantize = parsed->has("--quantize-position");
    if ((no_draco || quantize) && out_format != Glb)
        throw UsageError{"--no-draco and --quantize-position apply only to .glb output"};
    if (quantize && no_draco) throw UsageError{"--quantize-position applies only with Draco"};

    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    if (!in_format)  // standard input: a PLY header, OBJ vertex lines, else XYZ
        in_format = bytes->starts_with("ply")                                              ? PointFormat::Ply
                    : bytes->starts_with("v ") || bytes->find("\nv ") != std::string::npos ? PointFormat::Obj
                                                                                           : PointFormat::Xyz;
    const std::string content_type = *in_format == PointFormat::Ply   ? "application/ply"
                                     : *in_format == PointFormat::Obj ? "model/obj"
                                                                      : "text/x-xyz";
    const api::ApiRequest request =
        upload_request("/pointcloud", content_type, *bytes, file_query(*parsed, options, out_format));
    return finish(api::dispatch(request, context), *parsed, [&](const api::ApiResponse& response) {
        parsed->report() << "wrote " << parsed->output_label() << ": " << header(response, "X-Output-Points")
                         << " points" << (header(response, "X-Normals") == "true" ? ", normals" : "")
                         << (header(response, "X-Colors") == "true" ? ", colors" : "") << ", in "
                         << header(response, "X-Elapsed-Ms") << " ms\n";
    });
}

}  // namespace surfaced::cli
