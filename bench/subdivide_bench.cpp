// Uniform subdivision: ours vs OpenSubdiv Far on the same meshes, in one run.
//
// OpenSubdiv's side is what a user of Far does for the same result: TopologyRefinerFactory::Create, RefineUniform, then
// PrimvarRefinerReal<double>::Interpolate level by level (double positions, like ours). Times are the best of several
// repetitions (OpenSubdiv, ours, ours with two threads, interleaved), single-threaded but for the two-thread column.
// Peak memory is the peak of live heap bytes during the call, counted by the global operator new of
// bench/support/peak_memory.cpp (both libraries allocate through it), minus what was live before the call.
//
// Steady state, as in a long-running service: glibc is told to keep freed memory (M_MMAP_THRESHOLD/M_TRIM_THRESHOLD)
// so that neither side pays page faults for memory it allocated in the previous repetition; --cold measures without.
//
// Rows: each mesh plain (levels 1-4) and with creases (every 7th edge semi-sharp 2.5, every 97th vertex a corner of
// sharpness 3: the sharp rules and the fractional decay run at every level), same levels.
//
// Usage: bench_subdivide [--quick] [--cold] [--max-level N]
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <malloc.h>
#include <memory>
#include <string>
#include <vector>

#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/subdivide.h"
#include "bench/support/peak_memory.h"

namespace {
using namespace surfaced;
using namespace OpenSubdiv;

struct Point {
    double p[3];
    void Clear() { p[0] = p[1] = p[2] = 0; }
    void AddWithWeight(const Point& s, double w) {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
        p[2] += w * s.p[2];
    }
};

// Returns the number of refined faces (so the work cannot be optimised away).
std::size_t run_osd(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels) {
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::vector<int> vpf(mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) vpf[f] = static_cast<int>(mesh.face_size(f));
    Far::TopologyDescriptor desc;
    desc.numVertices = static_cast<int>(mesh.vertex_count());
    desc.numFaces = static_cast<int>(mesh.face_count());
    desc.numVertsPerFace = vpf.data();
    desc.vertIndicesPerFace = reinterpret_cast<const int*>(mesh.face_indices.data());
    std::vector<int> crease_pairs, corner_vertices;
    std::vector<float> crease_weights, corner_weights;
    for (const Crease& c : mesh.tags.creases) {
        crease_pairs.push_back(static_cast<int>(c.v0));
        crease_pairs.push_back(static_cast<int>(c.v1));
        crease_weights.push_back(static_cast<float>(c.sharpness));
    }
    for (const Corner& c : mesh.tags.corners) {
        corner_vertices.push_back(static_cast<int>(c.vertex));
        corner_weights.push_back(static_cast<float>(c.sharpness));
    }
    desc.numCreases = static_cast<int>(crease_weights.size());
    desc.creaseVertexIndexPairs = crease_pairs.data();
    desc.creaseWeights = crease_weights.data();
    desc.numCorners = static_cast<int>(corner_weights.size());
    desc.cornerVertexIndices = corner_vertices.data();
    desc.cornerWeights = corner_weights.data();
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(
        desc, Factory::Options(scheme == SubdivisionScheme::Loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, sdc)));
    refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
    std::vector<Point> src(mesh.vertex_count()), dst;
    std::memcpy(static_cast<void*>(src.data()), mesh.positions.data(), sizeof(Point) * src.size());
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    for (int l = 1; l <= levels; ++l) {
        dst.resize(refiner->GetLevel(l).GetNumVertices());
        Point* out = dst.data();
        primvar.Interpolate(l, src.data(), out);
        src.swap(dst);
    }
    return static_cast<std::size_t>(refiner->GetLevel(levels).GetNumFaces()) + (src[0].p[0] > 1e300 ? 1 : 0);
}

std::size_t run_ours(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels, int threads) {
    SubdivisionOptions options;
    options.scheme = scheme;
    options.levels = levels;
    options.threads = threads;
    auto out = subdivide(mesh, options);
    if (!out.ok()) {
        std::fprintf(stderr, "error: %s\n", out.error().message.c_str());
        std::exit(1);
    }
    return out->face_count();
}

//! The fastest of the repetitions, the peak of the last one, and the faces out.
struct Measure {
    bench::Measurement best;
    std::size_t faces = 0;
    double ms() const { return 1e3 * best.seconds; }
    double peak_mb() const { return best.peak_mib; }
};

// One repetition of f into m.
template <class F>
void measure_once(F&& f, Measure& m) {
    bench::keep_fastest(m.best, bench::measure([&] { m.faces = f(); }, bench::Clock::Wall));
}

PolygonMesh triangulated(const PolygonMesh& quads) {
    PolygonMesh m;
    m.positions = quads.positions;
    for (std::size_t f = 0; f < quads.face_count(); ++f) {
        auto q = quads.face(f);
        m.add_face({q[0], q[1], q[2]});
        m.add_face({q[0], q[2], q[3]});
    }
    return m;
}

// Every 7th edge (in order of first appearance) semi-sharp 2.5, every 97th vertex a corner of sharpness 3.
PolygonMesh creased(PolygonMesh m) {
    std::vector<std::vector<Index>> seen(m.vertex_count());
    std::size_t edge = 0;
    for (std::size_t f = 0; f < m.face_count(); ++f) {
        auto face = m.face(f);
        for (std::size_t j = 0; j < face.size(); ++j) {
            const Index a = std::min(face[j], face[(j + 1) % face.size()]);
            const Index b = std::max(face[j], face[(j + 1) % face.size()]);
            if (std::find(seen[a].begin(), seen[a].end(), b) != seen[a].end()) continue;
            seen[a].push_back(b);
            if (edge++ % 7 == 0) m.tags.creases.push_back({a, b, 2.5});
        }
    }
    for (std::size_t v = 0; v < m.vertex_count(); v += 97) m.tags.corners.push_back({static_cast<Index>(v), 3.0});
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false, cold = false;
    int max_level = 4;
    for (int i = 1; i < argc; ++i) {
        if (std::string(argv[i]) == "--quick") quick = true;
        if (std::string(argv[i]) == "--cold") cold = true;
        if (std::string(argv[i]) == "--max-level" && i + 1 < argc) max_level = std::atoi(argv[++i]);
    }
    if (quick) max_level = std::min(max_level, 2);
    if (!cold) {
        mallopt(M_MMAP_THRESHOLD, 1 << 30);
        mallopt(M_TRIM_THRESHOLD, -1);
    }

    struct Case {
        std::string name;
        PolygonMesh mesh;
        SubdivisionScheme scheme;
    };
    std::vector<Case> cases;
    // ~10k and ~100k input faces; the irregular torus has valence 3 and 5 vertices.
    cases.push_back({"torus 10k quads", shapes::torus(100, 100), SubdivisionScheme::CatmullClark});
    cases.push_back({"torus 10k tris", triangulated(shapes::torus(71, 71)), SubdivisionScheme::Loop});
    if (!quick) {
        cases.push_back({"torus 100k quads", shapes::torus(316, 316), SubdivisionScheme::CatmullClark});
        cases.push_back({"torus 100k tris", triangulated(shapes::torus(224, 224)), SubdivisionScheme::Loop});
    }
    for (std::size_t i = 0, plain = cases.size(); i < plain; ++i)
        cases.push_back({cases[i].name + ", creases", creased(cases[i].mesh), cases[i].scheme});

    std::printf(
        "| mesh | scheme | faces in | level | faces out | OpenSubdiv ms | ours ms | ratio | ours 2 threads ms | "
        "ratio | OpenSubdiv peak MiB | ours peak MiB | ratio |\n");
    std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const Case& c : cases) {
        for (int level = 1; level <= max_level; ++level) {
            const std::size_t out_faces = predicted_face_count(c.mesh, c.scheme, level);
            const int reps = out_faces > 2'000'000 ? 3 : (out_faces > 200'000 ? 5 : 10);
            // the three are interleaved, repetition by repetition, so that a busy moment on a shared machine hits
            // all of them rather than one
            Measure osd, ours, ours2;
            for (int r = 0; r < reps; ++r) {
                measure_once([&] { return run_osd(c.mesh, c.scheme, level); }, osd);
                measure_once([&] { return run_ours(c.mesh, c.scheme, level, 1); }, ours);
                measure_once([&] { return run_ours(c.mesh, c.scheme, level, 2); }, ours2);
            }
            if (osd.faces != ours.faces) {
                std::fprintf(stderr, "face counts differ: ours %zu, OpenSubdiv %zu\n", ours.faces, osd.faces);
                return 1;
            }
            std::printf("| %s | %s | %zu | %d | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.1f | %.1f | %.2f |\n",
                        c.name.c_str(), c.scheme == SubdivisionScheme::Loop ? "Loop" : "Catmull-Clark",
                        c.mesh.face_count(), level, ours.faces, osd.ms(), ours.ms(), ours.ms() / osd.ms(), ours2.ms(),
                        ours2.ms() / osd.ms(), osd.peak_mb(), ours.peak_mb(),
                        ours.peak_mb() / std::max(osd.peak_mb(), 1e-9));
            std::fflush(stdout);
        }
    }
    return 0;
}
