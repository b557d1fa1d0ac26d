// Spatial queries on triangle meshes (geometry/spatial), one thread, the same inputs for every side: hierarchy build
// time and memory; closest points per second against brute force and, in bench_spatial_peers, CGAL's AABB_tree;
// first-hit rays per second against brute force and Embree 3's single-ray path (rtcIntersect1); hierarchical winding
// numbers per second against the exact direct sum, with the largest error seen and the largest error bound; signed
// distances per second. Peak memory is the peak of live heap bytes during the build, counted by the global operator new
// of bench/support/peak_memory.cpp (Embree allocates its own memory and is not counted). Against a peer, the two sides
// are timed in turn, round by round. Queries are timed in thread CPU time, builds in wall time. Bench only, never
// linked into the service.
//
// Usage: bench_spatial [--quick] [--rounds N] [--rays]   (quick: the bunny only and fewer queries; rounds: each
// measurement's fastest of N runs, default 3; rays: the builds and the ray rows only)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <utility>
#include <random>
#include <string>
#include <vector>

#include "geometry/mesh/shapes.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/spatial/closest_point.h"
#include "geometry/spatial/ray_cast.h"
#include "geometry/spatial/signed_distance.h"
#include "geometry/spatial/winding_number.h"
#include "geometry/subdivision/subdivide.h"
#include "bench/support/bench_data.h"
#include "bench/support/peak_memory.h"
#if SURFACED_BENCH_PEERS
#include "bench/spatial_peers.h"
#endif

namespace {

using namespace surfaced;

int g_rounds = 3;

//! Bytes in MiB with one decimal.
std::string mib(std::size_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", static_cast<double>(bytes) / (1024.0 * 1024.0));
    return text;
}
bool g_rays_only = false;

//! Fastest of g_rounds runs, in seconds, and the live-heap peak above the start of the last run, in MiB.
using Timing = bench::Measurement;

//! Queries (single-threaded, ours and every peer's) are timed by the calling thread's CPU time: on a machine shared
//! with other work, a query loop's wall time also counts the time slices the scheduler gives other processes, its
//! thread time does not. Builds by wall time (thread_cpu false), since a peer may build on threads of its own.
Timing time_best(const std::function<void()>& step, int rounds = g_rounds, bool thread_cpu = true) {
    Timing t;
    for (int r = 0; r < rounds; ++r)
        bench::keep_fastest(t, bench::measure(step, thread_cpu ? bench::Clock::ThreadCpu : bench::Clock::Wall));
    return t;
}

#if SURFACED_BENCH_PEERS
//! Ours and a peer timed in turn, round by round (the machine's load changes less between the two than over a whole
//! run): the fastest of g_rounds for each.
std::pair<Timing, Timing> interleaved(const std::function<void()>& ours, const std::function<void()>& theirs) {
    Timing a, b;
    for (int r = 0; r < g_rounds; ++r) {
        a.seconds = std::min(a.seconds, time_best(ours, 1).seconds);
        b.seconds = std::min(b.seconds, time_best(theirs, 1).seconds);
    }
    return {a, b};
}
#endif

Vec3 random_in(std::mt19937_64& rng, const Box3& box, double margin) {
    const double pad = margin * box.diagonal();
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return {box.min.x - pad + u(rng) * (box.max.x - box.min.x + 2 * pad),
            box.min.y - pad + u(rng) * (box.max.y - box.min.y + 2 * pad),
            box.min.z - pad + u(rng) * (box.max.z - box.min.z + 2 * pad)};
}

struct Row {
    std::string mesh, query, reference;
    std::size_t triangles = 0;
    double ours = 0, theirs = 0;  // per second
    std::string note;
};
std::vector<Row> g_rows;

struct BuildRow {
    std::string mesh;
    std::size_t triangles = 0;
    double bvh_ms = 0, tree_ms = 0, bvh_mib = 0, nodes = 0, depth = 0;
    double cgal_ms = -1, cgal_mib = -1, embree_ms = -1;
};
std::vector<BuildRow> g_builds;

void run(const std::string& name, const PolygonMesh& input, std::size_t point_queries, std::size_t exact_queries) {
    const PolygonMesh mesh = input.is_triangle_mesh() ? input : triangulate(input);
    const std::size_t n = mesh.face_count();
    BuildRow build;
    build.mesh = name;
    build.triangles = n;

    TriangleBvh bvh;
    const Timing bvh_time = time_best([&] { bvh = std::move(build_bvh(mesh).value()); }, g_rounds, false);
    WindingTree tree;
    const Timing tree_time = time_best([&] { tree = build_winding_tree(bvh); }, g_rounds, false);
    build.bvh_ms = 1e3 * bvh_time.seconds;
    build.tree_ms = 1e3 * tree_time.seconds;
    build.bvh_mib = bvh_time.peak_mib;
    build.nodes = static_cast<double>(bvh.nodes.size());
    build.depth = static_cast<double>(bvh.depth);

    // the same inputs for every side
    std::mt19937_64 rng(42);
    const Box3 box = mesh.bounds();
    std::vector<Vec3> points(point_queries);
    for (Vec3& p : points) p = random_in(rng, box, 0.1);
    struct RayInput {
        Vec3 origin, direction;
    };
    std::vector<RayInput> rays(point_queries);
    const Vec3 centre = (box.min + box.max) * 0.5;
    for (RayInput& r : rays) {
        // from a sphere around the mesh towards a point of its box: most rays hit
        Vec3 d{std::normal_distribution<double>()(rng), std::normal_distribution<double>()(rng),
               std::normal_distribution<double>()(rng)};
        d *= 1.0 / norm(d);
        r.origin = centre + d * box.diagonal();
        r.direction = random_in(rng, box, 0.0) - r.origin;
    }

    // closest points
    std::vector<double> ours_distance(points.size());
    const std::size_t brute_n = std::min<std::size_t>(points.size(), std::max<std::size_t>(20, 20'000'000 / n));
    if (!g_rays_only) {
        const Timing cp = time_best([&] {
            for (std::size_t i = 0; i < points.size(); ++i) ours_distance[i] = closest_point(bvh, points[i])->distance;
        });
        std::size_t brute_differ = 0;
        const Timing cp_brute = time_best(
            [&] {
                for (std::size_t i = 0; i < brute_n; ++i) {
                    double best = 1e300;
                    for (const BvhTriangle& t : bvh.triangles) {
                        const Vec3 d = triangle_closest_point(points[i], t.p[0], t.p[1], t.p[2]).point - points[i];
                        best = std::min(best, dot(d, d));
                    }
                    brute_differ += std::fabs(std::sqrt(best) - ours_distance[i]) > 1e-12 * box.diagonal();
                }
            },
            1);
        g_rows.push_back({name, "closest point", "brute force", n, points.size() / cp.seconds,
                          brute_n / cp_brute.seconds,
                          std::to_string(brute_differ) + " of " + std::to_string(brute_n) + " distances differ"});
    }

    // rays
    std::vector<double> ours_t(rays.size());
    const Timing ray = time_best([&] {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const auto hit = ray_first_hit(bvh, {rays[i].origin, rays[i].direction});
            ours_t[i] = hit ? hit->t : -1.0;
        }
    });
    std::size_t ray_differ = 0;
    const Timing ray_brute = time_best(
        [&] {
            for (std::size_t i = 0; i < brute_n; ++i) {
                double best = -1;
                for (const BvhTriangle& t : bvh.triangles) {
                    const auto h = ray_triangle({rays[i].origin, rays[i].direction}, t.p[0], t.p[1], t.p[2]);
                    if (h && (best < 0 || h->t < best)) best = h->t;
                }
                ray_differ += best != ours_t[i];
            }
        },
        1);
    std::size_t hits = 0;
    for (double t : ours_t) hits += t >= 0;
    g_rows.push_back({name, "ray, first hit", "brute force", n, rays.size() / ray.seconds, brute_n / ray_brute.seconds,
                      std::to_string(100 * hits / std::max<std::size_t>(1, rays.size())) + "% of rays hit; " +
                          std::to_string(ray_differ) + " of " + std::to_string(brute_n) + " differ from brute force"});
    {
        // the same rays through the binary double-precision nodes alone (BvhOptions::ray_nodes false), in turn
        BvhOptions binary_only;
        binary_only.ray_nodes = false;
        const TriangleBvh binary = build_bvh(mesh, binary_only).value();
        std::size_t differ = 0;
        const auto layout_rays = [&] {
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const auto hit = ray_first_hit(bvh, {rays[i].origin, rays[i].direction});
                ours_t[i] = hit ? hit->t : -1.0;
            }
        };
        const auto binary_rays = [&] {
            differ = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const auto hit = ray_first_hit(binary, {rays[i].origin, rays[i].direction});
                differ += (hit ? hit->t : -1.0) != ours_t[i];
            }
        };
        Timing with_layout, without;
        for (int r = 0; r < g_rounds; ++r) {
            with_layout.seconds = std::min(with_layout.seconds, time_best(layout_rays, 1).seconds);
            without.seconds = std::min(without.seconds, time_best(binary_rays, 1).seconds);
        }
        g_rows.push_back(
            {name, "ray, first hit", "ours, binary double nodes", n, rays.size() / with_layout.seconds,
             rays.size() / without.seconds,
             std::to_string(differ) + " t differ; memory_bytes " + mib(bvh.memory_bytes()) +
                 " MiB, of which the layout " +
                 mib(bvh.ray_nodes.capacity() * sizeof(RayNode) + bvh.ray_triangles.capacity() * sizeof(RayTriangles)) +
                 " MiB"});
    }

    // winding numbers: the fast ones on every point, the exact sum on the first exact_queries
    if (!g_rays_only) {
        WindingNumberOptions exact_options;
        exact_options.exact = true;
        const std::size_t exact_n = std::min(exact_queries, points.size());
        std::vector<double> exact(exact_n);
        const Timing wn_exact = time_best(
            [&] {
                for (std::size_t i = 0; i < exact_n; ++i)
                    exact[i] = winding_number(bvh, tree, points[i], exact_options)->value;
            },
            1);
        for (double accuracy : {2.0, 3.0}) {
            WindingNumberOptions options;
            options.accuracy = accuracy;
            std::vector<double> fast(points.size()), bound(points.size());
            const Timing wn = time_best([&] {
                for (std::size_t i = 0; i < points.size(); ++i) {
                    const auto w = winding_number(bvh, tree, points[i], options).value();
                    fast[i] = w.value;
                    bound[i] = w.error_bound;
                }
            });
            double worst = 0, worst_bound = 0;
            for (std::size_t i = 0; i < exact_n; ++i) {
                worst = std::max(worst, std::fabs(exact[i] - fast[i]));
                worst_bound = std::max(worst_bound, bound[i]);
            }
            char note[128];
            std::snprintf(note, sizeof note, "largest error %.1e over %zu points (largest bound %.1e)", worst, exact_n,
                          worst_bound);
            char query[64];
            std::snprintf(query, sizeof query, "winding number, accuracy %.0f", accuracy);
            g_rows.push_back(
                {name, query, "exact direct sum", n, points.size() / wn.seconds, exact_n / wn_exact.seconds, note});
        }

        const Timing sd = time_best([&] {
            for (const Vec3& p : points) (void)signed_distance(bvh, tree, p)->distance;
        });
        g_rows.push_back({name, "signed distance", "-", n, points.size() / sd.seconds, 0, ""});
    }

#if SURFACED_BENCH_PEERS
    std::vector<double> positions, queries, out, ray_values, embree_t;
    std::vector<unsigned> triangles;
    for (const Vec3& p : mesh.positions) positions.insert(positions.end(), {p.x, p.y, p.z});
    triangles.assign(mesh.face_indices.begin(), mesh.face_indices.end());
    for (const Vec3& p : points) queries.insert(queries.end(), {p.x, p.y, p.z});
    for (const RayInput& r : rays)
        ray_values.insert(ray_values.end(),
                          {r.origin.x, r.origin.y, r.origin.z, r.direction.x, r.direction.y, r.direction.z});

    std::unique_ptr<bench::CgalTree> cgal;
    if (!g_rays_only) {
        const Timing cgal_build = time_best(
            [&] {
                cgal.reset();
                cgal = std::make_unique<bench::CgalTree>(positions, triangles);
            },
            g_rounds, false);
        build.cgal_ms = 1e3 * cgal_build.seconds;
        build.cgal_mib = cgal_build.peak_mib;
        const auto [cp_ours, cgal_cp] = interleaved(
            [&] {
                for (std::size_t i = 0; i < points.size(); ++i)
                    ours_distance[i] = closest_point(bvh, points[i])->distance;
            },
            [&] { cgal->closest_points(queries, out); });
        std::size_t disagree = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const double d = norm(Vec3{out[3 * i], out[3 * i + 1], out[3 * i + 2]} - points[i]);
            disagree += std::fabs(d - ours_distance[i]) > 1e-9 * box.diagonal();
        }
        g_rows.push_back({name, "closest point", "CGAL AABB_tree " + bench::cgal_version(), n,
                          points.size() / cp_ours.seconds, points.size() / cgal_cp.seconds,
                          std::to_string(disagree) + " distances differ by > 1e-9 diagonal"});
    }

    std::unique_ptr<bench::EmbreeScene> embree;
    const Timing embree_build = time_best(
        [&] {
            embree.reset();
            embree = std::make_unique<bench::EmbreeScene>(positions, triangles);
        },
        g_rounds, false);
    if (!embree->error.empty()) {
        std::fprintf(stderr, "Embree: %s\n", embree->error.c_str());
    } else {
        build.embree_ms = 1e3 * embree_build.seconds;
        const auto [ray_ours, embree_rays] = interleaved(
            [&] {
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    const auto hit = ray_first_hit(bvh, {rays[i].origin, rays[i].direction});
                    ours_t[i] = hit ? hit->t : -1.0;
                }
            },
            [&] { embree->first_hits(ray_values, embree_t); });
        std::size_t differ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const bool a = ours_t[i] >= 0, b = embree_t[i] >= 0;
            differ += a != b || (a && std::fabs(ours_t[i] - embree_t[i]) > 1e-4 * std::max(1.0, ours_t[i]));
        }
        g_rows.push_back({name, "ray, first hit", "Embree " + bench::embree_version() + " rtcIntersect1", n,
                          rays.size() / ray_ours.seconds, rays.size() / embree_rays.seconds,
                          std::to_string(differ) + " rays differ (hit or t by > 1e-4; Embree is float)"});
    }
#endif
    g_builds.push_back(build);
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) quick = true;
        if (std::strcmp(argv[i], "--rays") == 0) g_rays_only = true;
        if (std::strcmp(argv[i], "--rounds") == 0 && i + 1 < argc) g_rounds = std::max(1, std::atoi(argv[++i]));
    }
    const std::size_t queries = quick ? 20'000 : 100'000;
    const PolygonMesh bunny = bench::read_bunny();
    if (bunny.face_count() > 0) run("bunny", bunny, queries, quick ? 50 : 200);
    if (!quick) {
        // 250 x 200 quads, split in two: 100k triangles
        run("torus 100k", shapes::torus(250, 200), queries, 200);
        if (bunny.face_count() > 0) {
            SubdivisionOptions loop;
            loop.scheme = SubdivisionScheme::Loop;
            loop.levels = 1;
            run("bunny, Loop 1", subdivide(bunny, loop).value(), queries, 50);
        }
    }

    std::printf("Build, one thread, fastest of %d; peak: live heap during the build\n\n", g_rounds);
    std::printf(
        "| mesh | triangles | BVH ms | nodes | depth | BVH peak MiB | winding tree ms | CGAL AABB_tree + accelerate ms "
        "| "
        "CGAL peak MiB | Embree build ms |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const BuildRow& b : g_builds) {
        std::printf("| %s | %zu | %.1f | %.0f | %.0f | %.1f | %.1f | ", b.mesh.c_str(), b.triangles, b.bvh_ms, b.nodes,
                    b.depth, b.bvh_mib, b.tree_ms);
        if (b.cgal_ms >= 0)
            std::printf("%.1f | %.1f | ", b.cgal_ms, b.cgal_mib);
        else
            std::printf("- | - | ");
        if (b.embree_ms >= 0)
            std::printf("%.1f |\n", b.embree_ms);
        else
            std::printf("- |\n");
    }
    std::printf("\nQueries per second, one thread, the same %zu random points (box + 10%%) and rays for every side\n\n",
                queries);
    std::printf("| mesh | triangles | query | ours /s | reference | reference /s | ours / reference | notes |\n");
    std::printf("|---|---:|---|---:|---|---:|---:|---|\n");
    for (const Row& r : g_rows) {
        if (r.theirs > 0)
            std::printf("| %s | %zu | %s | %.0f | %s | %.0f | %.2f | %s |\n", r.mesh.c_str(), r.triangles,
                        r.query.c_str(), r.ours, r.reference.c_str(), r.theirs, r.ours / r.theirs, r.note.c_str());
        else
            std::printf("| %s | %zu | %s | %.0f | - | - | - | %s |\n", r.mesh.c_str(), r.triangles, r.query.c_str(),
                        r.ours, r.note.c_str());
    }
    return 0;
}
