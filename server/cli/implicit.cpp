// `surfaced implicit`: a scene file meshed through POST /implicit/mesh, with the command's options laid over it.
#include <iostream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/operations/implicit_mesh.h"
#include "server/cli/commands.h"
#include "server/cli/requests.h"

namespace surfaced::cli {
namespace {

constexpr std::string_view kImplicitHelp =
    R"(Usage: surfaced implicit SCENE.json -o OUT [--bounds B] [--resolution N | --cell-size H] [options]

Meshes the zero level set of an implicit scene inside its bounds, through the same operation as POST /implicit/mesh
(dual marching cubes with QEF vertices: closed, manifold, consistently oriented, sharp edges kept). Where the
surface meets the bounds it is closed by flat caps. SCENE.json (- for standard input) is a request body:
  {"scene": {"op": "difference", "args": [...]}, "bounds": [[x0,y0,z0],[x1,y1,z1]], "resolution": 64}
or the scene alone, {"op": "difference", "args": [...]}, with --bounds.
  OUT: .obj .ply .glb .gltf .json

Options:
  -o, --output OUT            output file (required); - for standard output
  --format F                  output format instead of OUT's extension: obj ply glb gltf json (needed with -o -)
  --bounds X0,Y0,Z0,X1,Y1,Z1  the box to mesh in (default: the file's; required for a scene alone)
  --resolution N              cells along the longest side of the bounds (default: the file's, else 64)
  --cell-size H               cell size instead of a resolution
  --mode M                    uniform (default) or adaptive (skips empty space: cost follows the surface)
  --simplify-tolerance T      adaptive only: QEM-simplify flat regions to this Hausdorff distance
  --max-grid-cells N          refuse larger grids (default 16777216)
  --no-draco                  write uncompressed glTF (.glb, .gltf)
  --quantize-position BITS    Draco position quantization, 1..24 (default 14; .glb/.gltf only)
  --normals                   also write vertex normals (.glb .gltf .obj .ply)
  -h, --help                  this text
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

//! The POST /implicit/mesh body of SCENE.json: a request body as it is, or a scene alone (an object with "op" and
//! no "scene") as the request's "scene"; --bounds replaces the file's bounds or gives a bare scene its own. A file
//! that is not a JSON object goes to the operation unchanged, which reports where it breaks.
std::string implicit_request_body(const std::string& bytes, const Parsed& parsed) {
    nlohmann::json doc = nlohmann::json::parse(bytes, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return bytes;
    const bool bare_scene = !doc.contains("scene") && doc.contains("op");
    if (!bare_scene && !parsed.has("--bounds")) return bytes;  // unchanged, so that errors keep their offsets
    if (bare_scene) {
        if (!parsed.has("--bounds"))
            throw UsageError{"implicit: " + parsed.input_label() +
                             " is a scene alone (no \"scene\" member): give --bounds xmin,ymin,zmin,xmax,ymax,zmax"};
        doc = nlohmann::json{{"scene", std::move(doc)}};
    }
    std::vector<double> v;
    std::istringstream in(parsed.value("--bounds"));
    for (std::string number; std::getline(in, number, ',');) v.push_back(std::stod(number));
    doc["bounds"] = nlohmann::json::array({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}});
    return doc.dump();
}

}  // namespace

int implicit(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--bounds", "", checked_bounds},
        {"--resolution", "", integer(2, 65536)},
        {"--cell-size", "", real()},
        {"--mode", "", one_of_names({"uniform", "adaptive"})},
        {"--simplify-tolerance", "", real()},
        {"--max-grid-cells", "", integer(1, 1'000'000'000'000LL)},
        {"--quantize-position", "", integer(1, 24)},
        flag("--no-draco"),
        flag("--normals"),
    };
    const auto parsed = parse_file_command(args, "implicit", kImplicitHelp, options, "SCENE.json");
    if (!parsed) return kExitOk;
    if (parsed->has("--resolution") && parsed->has("--cell-size"))
        throw UsageError{"give --resolution or --cell-size, not both"};
    const api::OutputFormat out_format = mesh_output_format(*parsed);
    check_mesh_output_options(*parsed, out_format);
    // The overrides implicit_mesh_from_file lays over the file's request.
    api::operations::ImplicitMeshOverrides overrides;
    if (parsed->has("--resolution")) overrides.resolution = std::stoll(parsed->value("--resolution"));
    if (parsed->has("--cell-size")) overrides.cell_size = std::stod(parsed->value("--cell-size"));
    if (parsed->has("--mode")) overrides.mode = parsed->value("--mode");
    if (parsed->has("--simplify-tolerance"))
        overrides.simplify_tolerance = std::stod(parsed->value("--simplify-tolerance"));
    if (parsed->has("--max-grid-cells")) context.limits.max_grid_cells = std::stoull(parsed->value("--max-grid-cells"));
    overrides.output.format = out_format;
    if (parsed->has("--no-draco") && is_gltf(out_format)) overrides.output.draco = false;
    if (parsed->has("--quantize-position"))
        overrides.output.quantize_position = std::stoll(parsed->value("--quantize-position"));
    if (parsed->has("--normals")) overrides.output.normals = true;

    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    return finish(
        api::operations::implicit_mesh_from_file(implicit_request_body(*bytes, *parsed), overrides, context), *parsed,
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
