// The mesh file commands: `surfaced subdivide`, `simplify`, `remesh` and `repair`, each the raw-file form of its
// POST endpoint.
#include <iostream>
#include <optional>
#include <string_view>
#include <vector>

#include "server/cli/commands.h"
#include "server/cli/requests.h"

namespace surfaced::cli {
namespace {

CheckValue mesh_input_formats() { return one_of_names({"obj", "off", "ply", "stl", "glb", "gltf"}); }

constexpr std::string_view kSubdivideHelp = R"(Usage: surfaced subdivide IN -o OUT [options]

Subdivides the mesh in IN and writes it to OUT, through the same operation as POST /subdivide.
Formats come from the file extensions:
  IN:  .obj .off .ply .stl .glb .gltf
  OUT: .obj .ply .glb .gltf (glTF, Draco-compressed unless --no-draco; .gltf is one JSON file with the
       data embedded) .json ({"mesh": ..., "stats": ...})

Options:
  -o, --output OUT          output file (required); - for standard output
  --format F                output format instead of OUT's extension: obj ply glb gltf json (needed with -o -)
  --input-format F          IN's format instead of its extension: obj off ply stl glb gltf (IN -: sniffed)
  --scheme S                catmull-clark (default) or loop (triangle meshes only)
  --levels N                refinement levels (default 1)
  --boundary B              edge-only, edge-and-corner or none (default: the file's
                            `t interpolateboundary` tag, else edge-only)
  --crease-method M         uniform (default) or chaikin: how semi-sharp creases decay
  --triangle-rule R         catmark (default) or smooth: Catmull-Clark weights next to triangles
  --loop-weights W          loop (default, as OpenSubdiv) or warren (3/(8n); not OpenSubdiv's surface)
  --uv-interpolation M      texture coordinates: none, corners-only, corners-plus1 (default),
                            corners-plus2, boundaries or all (OpenSubdiv's FVAR_LINEAR_*)
  --limit-surface           project the result onto the limit surface (normals from limit tangents)
  --max-faces N             use the largest level (up to --levels, if given) with at most N faces
  --no-draco                write uncompressed glTF (.glb, .gltf)
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb only)
  --normals                 also write vertex normals (.glb .obj .ply)
  --max-output-faces N      refuse if the result would have more faces (default 4000000)
  -h, --help                this text
)";

constexpr std::string_view kSimplifyHelp =
    R"(Usage: surfaced simplify IN -o OUT (--target-faces N | --ratio R | --max-error E) [options]

Simplifies the mesh in IN by quadric-error edge collapse and writes it to OUT, through the same operation as
POST /simplify. Polygons are triangulated first. Stops at whichever of the given criteria is reached first.
  IN:  .obj .off .ply .stl .glb .gltf  OUT: .obj .ply .glb .gltf .json

Options:
  -o, --output OUT          output file (required); - for standard output
  --format F                output format instead of OUT's extension: obj ply glb gltf json (needed with -o -)
  --input-format F          IN's format instead of its extension: obj off ply stl glb gltf (IN -: sniffed)
  --target-faces N          stop at N triangles or fewer
  --ratio R                 stop at R times the input's triangles, 0 < R <= 1
  --max-error E             keep the Hausdorff distance to the input <= E (model units)
  --lock-border             boundary vertices stay exactly where they are
  --locked-vertices LIST    vertices that stay exactly where they are (0-based indices into IN: 0,5,100)
  --restore-volume A        volume restoration, 0..1 (default 0): 1 keeps the volume, 0.5 lowers the RMS error
                            by 4-20% on smooth meshes, for 0-14% more time
  --threads N               1 (default) or 2: meshes of 20,000 triangles or more first collapse on two
                            threads, one half of the mesh each; 1.3-2x faster, a slightly different result
  --report-error            measure and print the Hausdorff and RMS distance to the input
  --repair MODE             auto (default): repair the mesh first when it needs it (printed on stderr);
                            none: refuse a non-manifold mesh
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb/.gltf only)
  --normals                 also write vertex normals (.glb .gltf .obj .ply)
  -h, --help                this text
)";

constexpr std::string_view kRemeshHelp =
    R"(Usage: surfaced remesh IN -o OUT [--edge-length L] [--iterations K] [options]

Remeshes the mesh in IN isotropically (split, collapse, flip, relax, project; Botsch-Kobbelt) towards edges of
length L and writes it to OUT, through the same operation as POST /remesh. Polygons are triangulated first. Sharp
edges and the boundary are kept. Prints the triangle quality before and after and the Hausdorff distance.
  IN:  .obj .off .ply .stl .glb .gltf  OUT: .obj .ply .glb .gltf .json

Options:
  -o, --output OUT          output file (required); - for standard output
  --format F                output format instead of OUT's extension: obj ply glb gltf json (needed with -o -)
  --input-format F          IN's format instead of its extension: obj off ply stl glb gltf (IN -: sniffed)
  --edge-length L           target edge length in model units (default: the input's mean edge length)
  --iterations K            rounds of split/collapse/flip/relax, 0..100 (default 10)
  --feature-angle DEG       dihedral angle above which an edge is sharp, 0..180 (default 60; 180: none)
  --free-boundary           relax boundary vertices like interior ones (default: keep the boundary)
  --smoothing S             tangential (default), laplacian or none
  --repair MODE             auto (default): repair the mesh first when it needs it (printed on stderr);
                            none: refuse a non-manifold mesh
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb/.gltf only)
  --normals                 also write vertex normals (.glb .gltf .obj .ply)
  -h, --help                this text
)";

constexpr std::string_view kRepairHelp =
    R"(Usage: surfaced repair IN -o OUT [options]

Repairs the mesh in IN and writes it to OUT, through the same operation as POST /repair: welds vertices at the same
position, drops degenerate and duplicate faces, orients faces consistently (outward for closed parts), cuts
non-manifold edges and vertices apart, drops unreferenced vertices; optionally drops small components and fills small
holes. Prints what it did on stderr ("repaired IN: welded=...; ..."), the summary on stdout.
  IN:  .obj .off .ply .stl .glb .gltf  OUT: .obj .ply .glb .gltf .json

Options:
  -o, --output OUT          output file (required); - for standard output
  --format F                output format instead of OUT's extension: obj ply glb gltf json (needed with -o -)
  --input-format F          IN's format instead of its extension: obj off ply stl glb gltf (IN -: sniffed)
  --weld-tolerance D        also weld vertices closer than D (model units; default 0: identical positions only)
  --no-orient               leave the faces' orientation as it is
  --min-component-faces N   drop connected components with fewer than N faces (default 0: keep all)
  --max-hole-edges N        fill holes with at most N boundary edges, 0..10000 (default 0: none)
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb/.gltf only)
  --normals                 also write vertex normals (.glb .gltf .obj .ply)
  -h, --help                this text
)";

}  // namespace

int subdivide(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--scheme", "scheme", one_of(api::kSchemeNames)},
        {"--levels", "levels", integer(0, 1'000'000)},
        {"--boundary", "boundary", one_of(api::kBoundaryNames)},
        {"--crease-method", "crease_method", one_of(api::kCreaseMethodNames)},
        {"--triangle-rule", "triangle_rule", one_of(api::kTriangleRuleNames)},
        {"--loop-weights", "loop_weights", one_of(api::kLoopWeightNames)},
        {"--uv-interpolation", "uv_interpolation", one_of(api::kUvInterpolationNames)},
        {"--max-faces", "max_faces", integer(1, 4'000'000'000LL)},
        flag("--limit-surface", "limit_surface"),
        {"--quantize-position", "quantize_position", integer(1, 24)},
        {"--max-output-faces", "", integer(1, 4'000'000'000LL)},
        flag("--no-draco"),
        flag("--normals", "normals"),
        {"--input-format", "", mesh_input_formats()},
    };
    const auto parsed = parse_file_command(args, "subdivide", kSubdivideHelp, options);
    if (!parsed) return kExitOk;
    const std::optional<MeshFormat> in_format = mesh_input_format(*parsed);
    const api::OutputFormat out_format = mesh_output_format(*parsed);
    check_mesh_output_options(*parsed, out_format);
    if (parsed->has("--max-output-faces"))
        context.limits.max_output_faces = std::stoull(parsed->value("--max-output-faces"));

    return upload_mesh(
        "/subdivide", *parsed, options, in_format, out_format, context, [&](const api::ApiResponse& response) {
            parsed->report() << "wrote " << parsed->output_label() << ": " << header(response, "X-Output-Vertices")
                             << " vertices, " << header(response, "X-Output-Faces") << " faces (from "
                             << header(response, "X-Input-Vertices") << " vertices, "
                             << header(response, "X-Input-Faces") << " faces) in " << header(response, "X-Elapsed-Ms")
                             << " ms\n";
        });
}

int simplify(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--target-faces", "target_faces", integer(0, 4'000'000'000LL)},
        {"--ratio", "ratio", real()},
        {"--max-error", "max_error", real()},
        flag("--lock-border", "lock_border"),
        {"--restore-volume", "restore_volume", real()},
        {"--threads", "threads", integer(1, 2)},
        {"--locked-vertices", "locked_vertices", any_text()},
        flag("--report-error", "report_error"),
        {"--repair", "repair", one_of(api::kRepairModeNames)},
        {"--quantize-position", "quantize_position", integer(1, 24)},
        flag("--no-draco"),
        flag("--normals", "normals"),
        {"--input-format", "", mesh_input_formats()},
    };
    const auto parsed = parse_file_command(args, "simplify", kSimplifyHelp, options);
    if (!parsed) return kExitOk;
    if (!parsed->has("--target-faces") && !parsed->has("--ratio") && !parsed->has("--max-error"))
        throw UsageError{"simplify: give --target-faces, --ratio or --max-error"};
    const std::optional<MeshFormat> in_format = mesh_input_format(*parsed);
    const api::OutputFormat out_format = mesh_output_format(*parsed);
    check_mesh_output_options(*parsed, out_format);

    return upload_mesh("/simplify", *parsed, options, in_format, out_format, context,
                       [&](const api::ApiResponse& response) {
                           print_repairs(*parsed, response);
                           print_triangulated_result(*parsed, response);
                           parsed->report() << ", error " << header(response, "X-Achieved-Error") << " ("
                                            << header(response, "X-Relative-Error") << " of the bounding-box diagonal)";
                           if (parsed->has("--report-error"))
                               parsed->report() << ", Hausdorff " << header(response, "X-Hausdorff") << ", RMS "
                                                << header(response, "X-RMS");
                           parsed->report() << ", in " << header(response, "X-Elapsed-Ms") << " ms\n";
                       });
}

int remesh(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--edge-length", "edge_length", real()},
        {"--iterations", "iterations", integer(0, 100)},
        {"--feature-angle", "feature_angle", real()},
        {"--smoothing", "smoothing", one_of_names({"tangential", "laplacian", "none"})},
        flag("--free-boundary", "keep_boundary", "false"),
        {"--repair", "repair", one_of(api::kRepairModeNames)},
        {"--quantize-position", "quantize_position", integer(1, 24)},
        flag("--no-draco"),
        flag("--normals", "normals"),
        {"--input-format", "", mesh_input_formats()},
    };
    const auto parsed = parse_file_command(args, "remesh", kRemeshHelp, options);
    if (!parsed) return kExitOk;
    const std::optional<MeshFormat> in_format = mesh_input_format(*parsed);
    const api::OutputFormat out_format = mesh_output_format(*parsed);
    check_mesh_output_options(*parsed, out_format);

    return upload_mesh(
        "/remesh", *parsed, options, in_format, out_format, context, [&](const api::ApiResponse& response) {
            print_repairs(*parsed, response);
            print_triangulated_result(*parsed, response);
            parsed->report() << ", edge length " << header(response, "X-Edge-Length") << " (mean "
                             << header(response, "X-Mean-Edge-Length-After") << "), min angle "
                             << header(response, "X-Min-Angle-Before") << " -> "
                             << header(response, "X-Min-Angle-After") << " deg, below 30 deg "
                             << header(response, "X-Below-30-Before") << " -> " << header(response, "X-Below-30-After")
                             << ", radius ratio " << header(response, "X-Radius-Ratio-Before") << " -> "
                             << header(response, "X-Radius-Ratio-After") << ", Hausdorff "
                             << header(response, "X-Hausdorff") << ", in " << header(response, "X-Elapsed-Ms")
                             << " ms\n";
        });
}

int repair(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--weld-tolerance", "weld_tolerance", real()},
        flag("--no-orient", "orient", "false"),
        {"--min-component-faces", "min_component_faces", integer(0, 4'000'000'000LL)},
        {"--max-hole-edges", "max_hole_edges", integer(0, 10'000)},
        {"--quantize-position", "quantize_position", integer(1, 24)},
        flag("--no-draco"),
        flag("--normals", "normals"),
        {"--input-format", "", mesh_input_formats()},
    };
    const auto parsed = parse_file_command(args, "repair", kRepairHelp, options);
    if (!parsed) return kExitOk;
    const std::optional<MeshFormat> in_format = mesh_input_format(*parsed);
    const api::OutputFormat out_format = mesh_output_format(*parsed);
    check_mesh_output_options(*parsed, out_format);

    return upload_mesh(
        "/repair", *parsed, options, in_format, out_format, context, [&](const api::ApiResponse& response) {
            print_repairs(*parsed, response, true);
            parsed->report() << "wrote " << parsed->output_label() << ": " << header(response, "X-Output-Faces")
                             << " faces, " << header(response, "X-Output-Vertices") << " vertices (from "
                             << header(response, "X-Input-Faces") << " faces, " << header(response, "X-Input-Vertices")
                             << " vertices), in " << header(response, "X-Elapsed-Ms") << " ms\n";
        });
}

}  // namespace surfaced::cli
