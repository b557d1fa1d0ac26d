#include "server/cli/limit_flags.h"

#include <cstdint>
#include <stdexcept>
#include <variant>

#include "server/cli/args.h"

namespace surfaced::cli {
namespace {

struct LimitFlag {
    std::string_view flag;
    std::variant<std::uint64_t api::Limits::*, int api::Limits::*> member;
    long long min, max;
    std::string_view help;
};

// The ranges keep a typo from disabling a budget (0, or a value no machine could serve) and keep recursion-bound
// budgets (expression depth) below what a worker thread's stack holds.
constexpr long long kMany = 1'000'000'000'000LL;
const LimitFlag kLimitFlags[] = {
    {"--max-input-faces", &api::Limits::max_input_faces, 1, kMany, "largest input mesh, in faces"},
    {"--max-input-vertices", &api::Limits::max_input_vertices, 1, kMany, "largest input mesh, in vertices"},
    {"--max-patches", &api::Limits::max_patches, 1, kMany, "Bezier patches in one request"},
    {"--max-patch-segments", &api::Limits::max_patch_segments, 1, 65536, "segments along one direction of one patch"},
    {"--max-grid-cells", &api::Limits::max_grid_cells, 8, kMany,
     "grid cells of implicit meshing, and of /reconstruct's finest level ((2^depth)^3)"},
    {"--max-scene-nodes", &api::Limits::max_scene_nodes, 1, kMany, "nodes in one implicit scene"},
    {"--max-expression-nodes", &api::Limits::max_expression_nodes, 1, kMany, "nodes of one algebraic expression"},
    {"--max-expression-depth", &api::Limits::max_expression_depth, 1, 512, "nesting depth of one expression"},
    {"--max-fractal-iterations", &api::Limits::max_fractal_iterations, 1, 10'000, "Mandelbulb and Menger iterations"},
    {"--max-level-set-samples", &api::Limits::max_level_set_samples, 8, kMany, "values of one level-set grid"},
    {"--max-query-points", &api::Limits::max_query_points, 1, kMany, "points + rays in one /implicit/query"},
    {"--max-ray-steps", &api::Limits::max_ray_steps, 1, 10'000'000, "sphere-tracing steps per ray"},
    {"--max-mesh-queries", &api::Limits::max_mesh_queries, 1, kMany, "points + rays in one /mesh/query"},
    {"--max-exact-winding-work", &api::Limits::max_exact_winding_work, 1, kMany,
     "points x triangles of exact winding numbers in one /mesh/query"},
    {"--max-points", &api::Limits::max_points, 1, kMany, "points in one point cloud (input or sampled)"},
    {"--max-reconstruct-depth", &api::Limits::max_reconstruct_depth, 2, 10, "octree depth of one /reconstruct"},
    {"--max-reconstruct-bytes", &api::Limits::max_reconstruct_bytes, 1, kMany,
     "predicted peak memory of one /reconstruct, in bytes"},
    {"--max-limit-points", &api::Limits::max_limit_points, 1, kMany, "points in one /limit/evaluate"},
};

}  // namespace

const std::vector<std::string_view>& limit_flag_names() {
    static const std::vector<std::string_view> names = [] {
        std::vector<std::string_view> out;
        for (const LimitFlag& f : kLimitFlags) out.push_back(f.flag);
        return out;
    }();
    return names;
}

bool apply_limit_flag(std::string_view flag, const std::string& text, api::Limits& limits) {
    for (const LimitFlag& f : kLimitFlags) {
        if (f.flag != flag) continue;
        const long long value = parse_number(flag, text, f.min, f.max);
        if (const auto* wide = std::get_if<std::uint64_t api::Limits::*>(&f.member))
            limits.*(*wide) = static_cast<std::uint64_t>(value);
        else
            limits.*(std::get<int api::Limits::*>(f.member)) = static_cast<int>(value);
        return true;
    }
    return false;
}

//! The default of a budget, from a default-constructed api::Limits.
static long long default_of(const LimitFlag& f) {
    static const api::Limits defaults;
    return std::visit([&](auto member) { return static_cast<long long>(defaults.*member); }, f.member);
}

Option limit_option(std::string_view flag) {
    for (const LimitFlag& f : kLimitFlags)
        if (f.flag == flag)
            return Option{.name = std::string(f.flag),
                          .check = integer(f.min, f.max),
                          .synopsis = std::string(f.flag) + " N",
                          .description = std::string(f.help) + " (default " + std::to_string(default_of(f)) + ")"};
    throw std::logic_error("limit_option: no budget flag " + std::string(flag));
}

std::string limit_flags_help() {
    std::string out;
    for (const LimitFlag& f : kLimitFlags) {
        // the help column of `serve --help`; a longer flag gets its help on the next line
        std::string synopsis = "  " + std::string(f.flag) + " N";
        synopsis += synopsis.size() < 25 ? std::string(25 - synopsis.size(), ' ') : "\n" + std::string(25, ' ');
        out += synopsis + std::string(f.help) + " (default " + std::to_string(default_of(f)) + ")\n";
    }
    return out;
}

}  // namespace surfaced::cli
