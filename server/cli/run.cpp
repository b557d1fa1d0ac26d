// `surfaced` itself: the main help and the dispatch to a command; usage errors become exit code 2 here.
#include <exception>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "server/cli.h"
#include "server/cli/commands.h"

#ifndef SURFACED_VERSION
#define SURFACED_VERSION "unknown"
#endif

namespace surfaced::cli {
namespace {

constexpr std::string_view kMainHelp =
    R"(surfaced - surface modeling over HTTP/JSON and on the command line: subdivision, simplification, remeshing,
repair, Bezier patches and curves, implicit surfaces, point clouds

Usage:
  surfaced serve [options]                    run the HTTP service
  surfaced healthcheck [options]              exit 0 when a running service answers GET /livez with 200
  surfaced subdivide IN -o OUT [options]      subdivide a mesh file
  surfaced tessellate IN -o OUT [options]     tessellate Bezier patches, B-spline surfaces (.bez/.bbp/.obj)
  surfaced simplify IN -o OUT [options]       simplify a mesh file (QEM edge collapse)
  surfaced remesh IN -o OUT [options]         isotropic remeshing to one edge length, quality report
  surfaced repair IN -o OUT [options]         repair a mesh (weld, orient, non-manifold cut apart), with a report
  surfaced implicit SCENE.json -o OUT [opts]  mesh an implicit scene (dual marching cubes, closed)
  surfaced pointcloud IN -o OUT [options]     convert a point cloud, estimate oriented normals
  surfaced reconstruct IN -o OUT [options]    closed surface from a point cloud (screened Poisson)
  surfaced curve IN -o OUT [options]          curve queries (Bezier, chains, SVG paths, B-splines); glTF lines
  surfaced surfaces IN.json -o OUT.json       B-spline/NURBS surface queries (POST /surfaces body), JSON answer
  surfaced query MESH --points P.json [opts]  inside, signed distance, closest point; ray hits on a mesh (JSON)
  surfaced grid IN --voxel-size H [opts]      narrow-band signed distance grid of a mesh or scene (JSON)
  surfaced limit MESH --points P.json [opts]  exact limit surface at (face, u, v): position, derivatives, UVs (JSON)
  surfaced <command> --help                   options of a command (those of its operation, as the API names them)
  surfaced --help | --version

IN - reads standard input (format from --input-format, else from the bytes); -o - writes standard output (with
--format), and the summary and reports then go to stderr:
  surfaced simplify - -o - --format obj --ratio 0.1 < in.stl > out.obj

Exit codes (the same in every command):
  0  success
  1  the operation failed: the input's geometry or format, a budget (--max-output-faces, levels, grid cells), a
     file that cannot be read or written; the problem is printed on stderr with its line, offset or field
  2  bad usage: an unknown command, option or value, a missing argument, a value out of its range or not
     applicable to the output format, whether the command line or the operation notices it
)";

const std::vector<std::string_view> kCommands = {"serve",  "healthcheck", "subdivide", "tessellate", "simplify",
                                                 "remesh", "repair",      "implicit",  "pointcloud", "reconstruct",
                                                 "curve",  "query",       "grid",      "surfaces",   "limit"};

}  // namespace

int run(int argc, char** argv) {
    try {
        if (argc < 2) {
            std::cerr << kMainHelp;
            return kExitUsage;
        }
        const std::string command = argv[1];
        Args args(argc, argv, 2);
        if (command == "-h" || command == "--help" || command == "help") {
            std::cout << kMainHelp;
            return kExitOk;
        }
        if (command == "--version" || command == "-V") {
            std::cout << "surfaced " << SURFACED_VERSION << "\n";
            return kExitOk;
        }
        if (command == "serve") return serve(args);
        if (command == "healthcheck") return healthcheck(args);
        if (command == "subdivide") return subdivide(args);
        if (command == "tessellate") return tessellate(args);
        if (command == "simplify") return simplify(args);
        if (command == "remesh") return remesh(args);
        if (command == "repair") return repair(args);
        if (command == "implicit") return implicit(args);
        if (command == "pointcloud") return pointcloud(args);
        if (command == "reconstruct") return reconstruct(args);
        if (command == "curve") return curve(args);
        if (command == "surfaces") return surfaces(args);
        if (command == "query") return query(args);
        if (command == "grid") return grid(args);
        if (command == "limit") return limit(args);
        std::string message = "unknown command \"" + command + "\" (";
        if (const auto match = closest_match(command, kCommands))
            message += "did you mean " + std::string(*match) + "? ";
        message +=
            "commands: serve, healthcheck, subdivide, tessellate, simplify, remesh, repair, implicit, pointcloud, "
            "reconstruct, curve, query, grid, surfaces, limit; see surfaced --help)";
        throw UsageError{message};
    } catch (const UsageError& e) {
        std::cerr << "surfaced: " << e.message << "\n";
        return kExitUsage;
    } catch (const std::exception& e) {
        std::cerr << "surfaced: internal error: " << e.what() << "\n";
        return kExitFailed;
    }
}

}  // namespace surfaced::cli
