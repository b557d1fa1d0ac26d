// NURBS surface evaluation, points per second: ours (geometry/surfaces/bspline_surface.h) against OpenCASCADE's
// Geom_BSplineSurface D0 / D1 / D2 on the same surfaces and the same random (u, v), one thread, each side timed in
// turn round by round, fastest round kept. Ours has no first-order-only evaluator: evaluate_derivatives always
// computes the second derivatives too, and is set against both D1 and D2.
//
//   build/bench/bench_surface_eval_occt [--quick] [--points N] [--rounds R]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bench/trim_peers.h"
#include "geometry/surfaces/bspline_surface.h"

namespace surfaced::bench {
namespace {

//! A wavy (p, q) surface over an n x n net with uniform clamped knots; rational with weights in [0.5, 2] if asked.
BSplineSurface make_surface(int p, int q, int n, bool rational, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> bump(-0.2, 0.2), weight(0.5, 2);
    BSplineSurface s;
    s.degree_u = p;
    s.degree_v = q;
    s.count_u = s.count_v = n;
    const auto knots = [n](int degree) {
        std::vector<double> k;
        for (int i = 0; i <= degree; ++i) k.push_back(0);
        for (int i = 1; i < n - degree; ++i) k.push_back(static_cast<double>(i) / (n - degree));
        for (int i = 0; i <= degree; ++i) k.push_back(1);
        return k;
    };
    s.knots_u = knots(p);
    s.knots_v = knots(q);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            s.points.push_back(
                {static_cast<double>(i), static_cast<double>(j), std::sin(i * 0.7) * std::cos(j) + bump(rng)});
            if (rational) s.weights.push_back(weight(rng));
        }
    return s;
}

double ours_evaluate(const BSplineSurface& s, const std::vector<double>& uv, int order, double& checksum) {
    double sum = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t k = 0; k + 1 < uv.size(); k += 2) {
        if (order == 0) {
            const Vec3 p = *evaluate(s, uv[k], uv[k + 1]);
            sum += p.x + p.y + p.z;
        } else {
            const PatchDerivatives d = *evaluate_derivatives(s, uv[k], uv[k + 1]);
            sum += d.position.x + d.position.y + d.position.z + d.du.x + d.dv.y;
            if (order == 2) sum += d.duu.z + d.duv.x + d.dvv.y;
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    checksum += sum;
    return seconds;
}

}  // namespace
}  // namespace surfaced::bench

int main(int argc, char** argv) {
    using namespace surfaced;
    using namespace surfaced::bench;
    std::size_t points = 200000;
    int rounds = 5;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--quick")) {
            points = 20000;
            rounds = 2;
        } else if (!std::strcmp(argv[i], "--points") && i + 1 < argc) {
            points = std::strtoull(argv[++i], nullptr, 10);
        } else if (!std::strcmp(argv[i], "--rounds") && i + 1 < argc) {
            rounds = std::atoi(argv[++i]);
        } else {
            std::fprintf(stderr, "usage: %s [--quick] [--points N] [--rounds R]\n", argv[0]);
            return 2;
        }
    }
    struct Case {
        const char* name;
        int p, q, n;
        bool rational;
    };
    const Case cases[] = {{"bicubic 12x12", 3, 3, 12, false},
                          {"bicubic 12x12, rational", 3, 3, 12, true},
                          {"quintic 12x12, rational", 5, 5, 12, true},
                          {"biquadratic 9x5, rational", 2, 2, 9, true}};
    std::printf(
        "| surface | evaluation | ours points/s | OCCT | OCCT points/s | ours / OCCT (rate) | largest |sum difference| "
        "|\n");
    std::printf("|---|---|---:|---|---:|---:|---:|\n");
    for (const Case& c : cases) {
        const BSplineSurface s = make_surface(c.p, c.q, c.n, c.rational, 7);
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> unit(0, 1);
        std::vector<double> uv(2 * points);
        for (double& x : uv) x = unit(rng);
        struct Pair {
            const char* ours;
            const char* occt;
            int ours_order, occt_order;
        };
        for (const Pair& pair : {Pair{"evaluate", "D0", 0, 0}, Pair{"evaluate_derivatives", "D1", 2, 1},
                                 Pair{"evaluate_derivatives", "D2", 2, 2}}) {
            double best_ours = INFINITY, best_occt = INFINITY, sum_ours = 0, sum_occt = 0;
            for (int r = 0; r < rounds; ++r) {
                double a = 0, b = 0;
                best_ours = std::min(best_ours, ours_evaluate(s, uv, pair.ours_order, a));
                best_occt = std::min(best_occt, occt_evaluate(s, uv, pair.occt_order, b));
                sum_ours = a;
                sum_occt = b;
            }
            // the checksums compare like with like when both sides computed the same orders
            const bool comparable = pair.ours_order == pair.occt_order;
            char diff[32] = "";
            if (comparable) std::snprintf(diff, sizeof diff, "%.1e", std::fabs(sum_ours - sum_occt));
            std::printf("| %s | %s | %.0f | %s | %.0f | %.2f | %s |\n", c.name, pair.ours, points / best_ours,
                        pair.occt, points / best_occt, best_occt / best_ours, comparable ? diff : "");
            std::fflush(stdout);
        }
    }
    return 0;
}
