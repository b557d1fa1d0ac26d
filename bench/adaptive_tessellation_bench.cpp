// The Catmull-Clark limit surface to a distance tolerance: ours (tessellate_limit, rates per edge from bounds on the
// surface) against the uniform refinement level that reaches the same tolerance (subdivide with limit positions,
// each quad counted as two triangles) and against OpenSubdiv's Bfr::Tessellation at the smallest uniform rate per
// face that reaches it (Bfr::Surface evaluated at its coordinates, approximation levels 10). One thread.
//
// The error of every output is measured the same way: the largest distance from exact limit samples (a 24 x 24 grid
// per quad domain, per N-gon sub-face, from LimitSurfaceEvaluator) to its triangles. The tolerance is relative to the
// bounding-box diagonal. Times: ours includes creating the evaluator; Bfr includes its factory and tessellation
// objects and the evaluation; uniform is subdivide() alone.
//
// Usage: bench_adaptive_tessellation [--quick] [--only NAME] [--relative R] [--plain] [--straddle F] [--threads N]
// (--only runs the rows whose mesh name contains NAME, --relative
// one tolerance R of the diagonal, --plain adds rows of ours with plain grids only, LimitTessellationOptions::stagger
// = false; --straddle F plans ours with LimitTessellationOptions::straddle = F instead of its default, kDefaultStraddle;
// "(on the surface)" rows are ours with straddle 0; --threads N plans ours with LimitTessellationOptions::threads = N,
// default 1)
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/spatial/bvh.h"
#include "geometry/spatial/closest_point.h"
#include "geometry/subdivision/adaptive_tessellation.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/subdivision/subdivide.h"
#include "bench/support/bench_data.h"
#include "bench/support/timing.h"

namespace {

using namespace surfaced;
using namespace OpenSubdiv;

std::unique_ptr<Far::TopologyRefiner> make_refiner(const PolygonMesh& mesh) {
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::vector<int> sizes(mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) sizes[f] = static_cast<int>(mesh.face_size(f));
    std::vector<int> indices(mesh.face_indices.begin(), mesh.face_indices.end());
    std::vector<int> pairs, corners;
    std::vector<float> weights, corner_weights;
    for (const Crease& c : mesh.tags.creases) {
        pairs.push_back(static_cast<int>(c.v0));
        pairs.push_back(static_cast<int>(c.v1));
        weights.push_back(static_cast<float>(c.sharpness));
    }
    for (const Corner& c : mesh.tags.corners) {
        corners.push_back(static_cast<int>(c.vertex));
        corner_weights.push_back(static_cast<float>(c.sharpness));
    }
    Far::TopologyDescriptor desc;
    desc.numVertices = static_cast<int>(mesh.vertex_count());
    desc.numFaces = static_cast<int>(mesh.face_count());
    desc.numVertsPerFace = sizes.data();
    desc.vertIndicesPerFace = indices.data();
    desc.numCreases = static_cast<int>(weights.size());
    desc.creaseVertexIndexPairs = pairs.data();
    desc.creaseWeights = weights.data();
    desc.numCorners = static_cast<int>(corners.size());
    desc.cornerVertexIndices = corners.data();
    desc.cornerWeights = corner_weights.data();
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    return std::unique_ptr<Far::TopologyRefiner>(Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
}

int subface_columns(std::size_t n) {
    return n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::sqrt(static_cast<float>(n - 1)));
}

//! Exact limit samples of the whole surface.
std::vector<Vec3> limit_samples(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& mesh, int steps) {
    std::vector<Vec3> out;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const std::size_t n = mesh.face_size(f);
        auto surface = evaluator.face_surface(f);
        if (!surface) continue;
        for (std::size_t d = 0; d < (n == 4 ? 1 : n); ++d)
            for (int j = 0; j < steps; ++j)
                for (int i = 0; i < steps; ++i) {
                    const double s = (i + 0.5) / steps, t = (j + 0.5) / steps;
                    double u = s, v = t;
                    if (n != 4) {
                        const int columns = subface_columns(n);
                        u = double(d % std::size_t(columns)) + 0.5 * s;
                        v = double(d / std::size_t(columns)) + 0.5 * t;
                    }
                    auto sample = surface->evaluate(u, v);
                    if (sample) out.push_back(sample->position);
                }
    }
    return out;
}

double max_distance(const std::vector<Vec3>& samples, const PolygonMesh& mesh) {
    auto bvh = build_bvh(mesh);
    if (!bvh) return INFINITY;
    double worst = 0;
    for (const Vec3& p : samples) {
        auto c = closest_point(*bvh, p);
        worst = std::max(worst, c ? c->distance : INFINITY);
    }
    return worst;
}

//! Bfr::Tessellation of every face at one uniform rate, evaluated with Bfr::Surface (vertices per face, not shared).
PolygonMesh bfr_tessellate(const PolygonMesh& mesh, int rate) {
    std::unique_ptr<Far::TopologyRefiner> refiner = make_refiner(mesh);
    Bfr::SurfaceFactory::Options options;
    options.SetApproxLevelSmooth(10);
    options.SetApproxLevelSharp(10);
    Bfr::RefinerSurfaceFactory<> factory(*refiner, options);
    std::vector<double> points;
    for (const Vec3& p : mesh.positions) points.insert(points.end(), {p.x, p.y, p.z});
    PolygonMesh out;
    Bfr::Surface<double> surface;
    std::vector<double> patch, coords;
    std::vector<int> facets;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        if (!factory.InitVertexSurface(static_cast<int>(f), &surface)) continue;
        patch.resize(3 * static_cast<std::size_t>(surface.GetNumPatchPoints()));
        surface.PreparePatchPoints(points.data(), 3, patch.data(), 3);
        Bfr::Tessellation tess(surface.GetParameterization(), rate, Bfr::Tessellation::Options());
        coords.resize(2 * static_cast<std::size_t>(tess.GetNumCoords()));
        tess.GetCoords(coords.data());
        const auto base = static_cast<Index>(out.positions.size());
        for (int i = 0; i < tess.GetNumCoords(); ++i) {
            double p[3];
            surface.Evaluate(&coords[2 * static_cast<std::size_t>(i)], patch.data(), 3, p);
            out.positions.push_back({p[0], p[1], p[2]});
        }
        facets.resize(3 * static_cast<std::size_t>(tess.GetNumFacets()));
        tess.GetFacets(facets.data());
        for (std::size_t k = 0; k < facets.size(); k += 3)
            out.add_face({base + Index(facets[k]), base + Index(facets[k + 1]), base + Index(facets[k + 2])});
    }
    return out;
}

std::string g_only;
double g_relative = 0;
bool g_plain = false;
int g_threads = 1;
double g_straddle = kDefaultStraddle;

//! One variant of ours: its row label's suffix and its options.
struct Kind {
    const char* suffix;
    bool guaranteed, stagger;
    double straddle;
};

void run(const char* name, const PolygonMesh& mesh, double relative, const Kind& kind) {
    if (!g_only.empty() && std::string(name).find(g_only) == std::string::npos) return;
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    if (!evaluator) {
        std::printf("%s: %s\n", name, evaluator.error().message.c_str());
        return;
    }
    const Box3 box = mesh.bounds();
    const double tolerance = relative * norm(box.max - box.min);
    const std::vector<Vec3> samples = limit_samples(*evaluator, mesh, 24);

    // ours
    bench::Stopwatch watch;
    auto fresh = LimitSurfaceEvaluator::create(mesh, {});
    LimitTessellationOptions options;
    options.tolerance = tolerance;
    options.max_segments = 1024;
    options.guaranteed = kind.guaranteed;
    options.stagger = kind.stagger;
    options.threads = g_threads;
    options.straddle = kind.straddle;
    auto ours = tessellate_limit(*fresh, mesh, options);
    const double ours_ms = watch.ms();
    if (!ours) {
        std::printf("%s: %s\n", name, ours.error().message.c_str());
        return;
    }
    const double ours_error = max_distance(samples, ours->mesh);

    // uniform: the first level whose limit mesh is within the tolerance
    int level = 0;
    std::size_t uniform_triangles = 0;
    double uniform_ms = 0, uniform_error = 0;
    for (int l = 1; l <= 8; ++l) {
        SubdivisionOptions sub;
        sub.levels = l;
        sub.limit_surface = true;
        watch.restart();
        auto refined = subdivide(mesh, sub);
        uniform_ms = watch.ms();
        uniform_error = max_distance(samples, *refined);
        uniform_triangles = 0;
        for (std::size_t f = 0; f < refined->face_count(); ++f) uniform_triangles += refined->face_size(f) - 2;
        level = l;
        if (uniform_error <= tolerance) break;
    }

    // Bfr: the smallest uniform rate within the tolerance (doubling, then bisection)
    int lo = 0, hi = 1;
    while (max_distance(samples, bfr_tessellate(mesh, hi)) > tolerance && hi < 512) {
        lo = hi;
        hi *= 2;
    }
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        (max_distance(samples, bfr_tessellate(mesh, mid)) > tolerance ? lo : hi) = mid;
    }
    watch.restart();
    const PolygonMesh bfr = bfr_tessellate(mesh, hi);
    const double bfr_ms = watch.ms();
    const double bfr_error = max_distance(samples, bfr);

    std::printf("| %s%s | %zu | %.0e | %zu | %.3g | %.2g | %d | %zu | %.3g | %.2g | %.2f | %d | %zu | %.3g | %.2f |\n",
                name, kind.suffix, mesh.face_count(), relative, ours->mesh.face_count(), ours_ms,
                ours_error / tolerance, level, uniform_triangles, uniform_ms, uniform_error / tolerance,
                double(ours->mesh.face_count()) / double(uniform_triangles), hi, bfr.face_count(),
                bfr_error / tolerance, ours_ms / bfr_ms);
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) quick = true;
        if (std::strcmp(argv[i], "--only") == 0 && i + 1 < argc) g_only = argv[++i];
        if (std::strcmp(argv[i], "--relative") == 0 && i + 1 < argc) g_relative = std::atof(argv[++i]);
        if (std::strcmp(argv[i], "--plain") == 0) g_plain = true;
        if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) g_threads = std::atoi(argv[++i]);
        if (std::strcmp(argv[i], "--straddle") == 0 && i + 1 < argc) g_straddle = std::atof(argv[++i]);
    }
    std::printf(
        "| mesh | faces | tolerance | ours tris | ours ms | ours err/tol | uniform level | uniform tris | "
        "uniform ms | uniform err/tol | ours/uniform tris | Bfr rate | Bfr tris | Bfr err/tol | ours/Bfr time |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    PolygonMesh creased = shapes::cube();
    for (Index v : {0u, 1u, 2u, 3u}) creased.tags.creases.push_back({v, (v + 1) % 4, 2.5});
    PolygonMesh top_sharp = shapes::cube();
    for (Index v : {4u, 5u, 6u, 7u}) top_sharp.tags.creases.push_back({v, v == 7 ? 4u : v + 1, 10.0});
    std::vector<double> relatives = quick ? std::vector<double>{1e-2} : std::vector<double>{1e-2, 1e-3};
    if (g_relative > 0) relatives = {g_relative};
    // guaranteed rates, then with plain grids only (--plain), then with every vertex on the surface, then measured
    // rates (which place every vertex on the surface)
    std::vector<Kind> kinds{{"", true, true, g_straddle}};
    if (g_plain) kinds.push_back({" (plain)", true, false, g_straddle});
    kinds.push_back({" (on the surface)", true, true, 0.0});
    kinds.push_back({" (measured)", false, true, 0.0});
    for (double relative : relatives)
        for (const Kind& k : kinds) {
            const auto row = [&](const char* name, const PolygonMesh& mesh) { run(name, mesh, relative, k); };
            row("cube", shapes::cube());
            row("cube, edge loop sharpness 2.5", creased);
            row("cube, top loop infinitely sharp", top_sharp);
            row("thin torus 12x8 (r = R/8)", shapes::torus(12, 8, 1.0, 0.125));
            row("irregular torus", shapes::irregular_torus());
            for (const char* name : {"catmark_pyramid_creases1", "catmark_torus_creases0", "catmark_car"}) {
                const PolygonMesh mesh = bench::read_opensubdiv_shape(name);
                if (mesh.face_count() > 0 && !(quick && std::strcmp(name, "catmark_car") == 0)) row(name, mesh);
            }
        }
    return 0;
}
