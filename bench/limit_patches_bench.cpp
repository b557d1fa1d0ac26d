// The limit surface as patches: ours (limit_patches: a uniform isolation level L, exact B-spline patches, bicubic
// approximations next to irregular vertices with a bound on their error) against OpenSubdiv's Far::PatchTable
// (adaptive isolation to level L, Gregory-basis end caps there, the default; double precision), side by side.
//
// For each shape and level: patch counts, time (ours: evaluator creation and limit_patches; Far: adaptive refinement,
// patch table, local points), and the error next to irregular vertices: the largest distance from the exact limit
// surface (LimitSurfaceEvaluator) on a 12 x 12 grid crowded towards the sides of every square ours approximates (the
// squares Far's end caps cover), for our patches and for Far's at the same (face, u, v); beside it our bound.
// Far's columns need quads only (its patch faces are the base quads there); "-" otherwise.
//
// Usage: bench_limit_patches [--quick]
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/primvarRefiner.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/support/bench_data.h"
#include "bench/support/timing.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/limit_patches.h"
#include "geometry/surfaces/bezier_patch.h"
#include "tests/support/osd_reference.h"

namespace {

using namespace surfaced;
using namespace OpenSubdiv;

//! A point for Far's primvar interpolation.
struct FarPoint {
    double x = 0, y = 0, z = 0;
    void Clear(void* = nullptr) { x = y = z = 0; }
    void AddWithWeight(const FarPoint& p, double w) {
        x += w * p.x;
        y += w * p.y;
        z += w * p.z;
    }
};

//! Far's patch table at adaptive isolation `level` with its default end caps, and the points it needs.
struct FarPatches {
    std::unique_ptr<Far::TopologyRefiner> refiner;
    std::unique_ptr<Far::PatchTable> table;
    std::unique_ptr<Far::PatchMap> map;
    std::vector<FarPoint> points;

    FarPatches(const PolygonMesh& mesh, int level) : refiner(testing::make_refiner(mesh, SubdivisionOptions{})) {
        Far::PatchTableFactory::Options options(static_cast<unsigned>(level));
        options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
        options.SetPatchPrecision<double>();
        options.useInfSharpPatch = true;
        refiner->RefineAdaptive(options.GetRefineAdaptiveOptions());
        table.reset(Far::PatchTableFactory::Create(*refiner, options));
        points.resize(static_cast<std::size_t>(refiner->GetNumVerticesTotal() + table->GetNumLocalPoints()));
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
            points[v] = {mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z};
        Far::PrimvarRefinerReal<double> primvar(*refiner);
        FarPoint* src = points.data();
        for (int l = 1; l <= refiner->GetMaxLevel(); ++l) {
            FarPoint* dst = src + refiner->GetLevel(l - 1).GetNumVertices();
            primvar.Interpolate(l, src, dst);
            src = dst;
        }
        // (ComputeLocalPointValues assumes single-precision stencils)
        if (auto* stencils = table->GetLocalPointStencilTable<double>())
            stencils->UpdateValues(points.data(), points.data() + refiner->GetNumVerticesTotal());
        map = std::make_unique<Far::PatchMap>(*table);
    }

    std::optional<Vec3> evaluate(std::size_t face, double u, double v) const {
        const Far::PatchTable::PatchHandle* handle = map->FindPatch(static_cast<int>(face), u, v);
        if (!handle) return std::nullopt;
        double w[20];
        table->EvaluateBasis(*handle, u, v, w);
        const Far::ConstIndexArray cvs = table->GetPatchVertices(*handle);
        Vec3 p{0, 0, 0};
        for (int i = 0; i < cvs.size(); ++i) {
            const FarPoint& q = points[static_cast<std::size_t>(cvs[i])];
            p += w[i] * Vec3{q.x, q.y, q.z};
        }
        return p;
    }
};

//! A grid parameter in (0, 1), crowded towards both ends (where the irregular vertices sit).
double graded(int i, int n) {
    const double y = (i + 0.5) / n;
    return y < 0.5 ? 0.5 * std::pow(2 * y, 3) : 1 - 0.5 * std::pow(2 - 2 * y, 3);
}

void run(const char* name, const PolygonMesh& mesh, int level) {
    bool quads = true;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) quads = quads && mesh.face_size(f) == 4;
    bench::Stopwatch watch;
    auto evaluator = LimitSurfaceEvaluator::create(mesh, SubdivisionOptions{});
    if (!evaluator) return;
    LimitPatchOptions options;
    options.levels = level;
    options.max_levels = 10;
    auto set = limit_patches(*evaluator, mesh, options);
    const double ours_ms = watch.ms();
    if (!set) {
        std::printf("| %s | %d | %s |\n", name, level, set.error().message.c_str());
        return;
    }
    std::optional<FarPatches> far;
    double far_ms = 0;
    if (quads) {
        watch.restart();
        far.emplace(mesh, level);
        far_ms = watch.ms();
    }
    const double diagonal = mesh.bounds().diagonal();
    constexpr int kGrid = 12;
    double ours_error = 0, far_error = 0;
    for (std::size_t p = 0; p < set->patches.size(); ++p) {
        if (set->exact[p]) continue;
        const auto& square = set->squares[p];
        for (int j = 0; j < kGrid; ++j)
            for (int i = 0; i < kGrid; ++i) {
                const double s = graded(i, kGrid), t = graded(j, kGrid);
                const double u = square[0] + square[2] * s, v = square[1] + square[2] * t;
                auto exact = evaluator->evaluate(set->faces[p], u, v);
                if (!exact) continue;
                ours_error = std::max(ours_error, norm(evaluate(set->patches[p], s, t) - exact->position));
                if (far)
                    if (auto q = far->evaluate(set->faces[p], u, v))
                        far_error = std::max(far_error, norm(*q - exact->position));
            }
    }
    if (far)
        std::printf("| %s | %d | %zu | %zu | %.3g | %.3g | %.2f | %d | %.3g | %.3g | %.2f |\n", name, level,
                    set->patches.size(), set->approximate_count, ours_ms, set->max_error / diagonal,
                    set->max_error / std::max(ours_error, 1e-300), far->table->GetNumPatchesTotal(), far_ms,
                    far_error / diagonal, far_error / std::max(set->max_error, 1e-300));
    else
        std::printf("| %s | %d | %zu | %zu | %.3g | %.3g | %.2f | - | - | - | - |\n", name, level, set->patches.size(),
                    set->approximate_count, ours_ms, set->max_error / diagonal,
                    set->max_error / std::max(ours_error, 1e-300));
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--quick") == 0) quick = true;
    std::printf(
        "| mesh | level | ours patches | ours approximated | ours ms | ours bound / diagonal | bound / largest sampled "
        "| Far patches | Far ms | Far error / diagonal | Far error / our bound |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    const std::vector<int> levels = quick ? std::vector<int>{2} : std::vector<int>{1, 2, 3, 4};
    for (int level : levels) {
        run("cube (valence 3)", shapes::cube(), level);
        for (const char* name : {"catmark_pole8", "catmark_torus_creases0", "catmark_cubes_semisharp",
                                 "catmark_pyramid_creases1", "catmark_car"}) {
            const PolygonMesh mesh = bench::read_opensubdiv_shape(name);
            if (mesh.face_count() > 0) run(name, mesh, level);
        }
    }
    return 0;
}
