#include "geometry/reconstruct/solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "geometry/core/two_parts.h"

namespace surfaced::reconstruct {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Sums are taken over fixed chunks, then the chunks' partial sums in order, so that they come out the same whether
// one thread or two compute the chunks.
constexpr std::size_t kChunk = 1 << 14;
// Levels with fewer unknowns than this run on one thread (a second one would cost more than it saves).
constexpr std::size_t kThreadedSize = 1 << 16;

//! Runs body(begin, end) over [0, n), on two threads (split at a chunk boundary) when `threaded`.
template <class F>
void split(std::size_t n, bool threaded, F&& body) {
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    const std::size_t middle = std::min(n, (chunks / 2) * kChunk);
    run_two_parts(threaded, [&](int part) {
        if (part == 0)
            body(std::size_t{0}, middle);
        else
            body(middle, n);
    });
}

double dot_product(const std::vector<double>& a, const std::vector<double>& b, bool threaded,
                   std::vector<double>& partial) {
    const std::size_t n = a.size();
    partial.assign((n + kChunk - 1) / kChunk, 0.0);
    split(n, threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; c += kChunk) {
            double sum = 0;
            for (std::size_t i = c; i < std::min(end, c + kChunk); ++i) sum += a[i] * b[i];
            partial[c / kChunk] = sum;
        }
    });
    double sum = 0;
    for (const double s : partial) sum += s;
    return sum;
}

//! Jacobi-preconditioned conjugate gradients on the free dofs, from x = 0. Returns false when cancelled.
bool conjugate_gradients(const LevelSystem& system, const std::vector<double>& rhs, const SolverOptions& options,
                         std::vector<double>& x, LevelSolveStats& stats) {
    const std::size_t n = system.size();
    const bool threaded = options.threads != 1 && n >= kThreadedSize;
    const std::vector<double>& diag = system.diagonal();
    const std::vector<char>& fixed = system.fixed();
    x.assign(n, 0.0);
    std::vector<double> r = rhs, z(n), p(n), ap, partial, partial_rz;
    for (std::size_t i = 0; i < n; ++i)
        if (fixed[i]) r[i] = 0;
    const double rhs_norm = std::sqrt(dot_product(r, r, threaded, partial));
    stats.iterations = 0;
    stats.relative_residual = 0;
    if (rhs_norm == 0) return true;
    for (std::size_t i = 0; i < n; ++i) z[i] = fixed[i] ? 0.0 : r[i] / diag[i];
    p = z;
    double rz = dot_product(r, z, threaded, partial);
    for (int it = 0; it < options.max_iterations; ++it) {
        if (options.cancel.requested()) return false;
        system.apply(p, ap, threaded);
        const double pap = dot_product(p, ap, threaded, partial);
        if (!(pap > 0)) break;
        const double step = rz / pap;
        // the update and the two dot products of the new residual in one pass, over the same chunks as
        // dot_product's (so the sums are the same)
        partial.assign((n + kChunk - 1) / kChunk, 0.0);
        partial_rz.assign(partial.size(), 0.0);
        split(n, threaded, [&](std::size_t begin, std::size_t end) {
            for (std::size_t c = begin; c < end; c += kChunk) {
                double rr_sum = 0, rz_sum = 0;
                for (std::size_t i = c; i < std::min(end, c + kChunk); ++i) {
                    x[i] += step * p[i];
                    r[i] -= step * ap[i];
                    z[i] = fixed[i] ? 0.0 : r[i] / diag[i];
                    rr_sum += r[i] * r[i];
                    rz_sum += r[i] * z[i];
                }
                partial[c / kChunk] = rr_sum;
                partial_rz[c / kChunk] = rz_sum;
            }
        });
        double rr = 0, rz_next = 0;
        for (const double v : partial) rr += v;
        for (const double v : partial_rz) rz_next += v;
        stats.iterations = it + 1;
        const double residual = std::sqrt(rr) / rhs_norm;
        stats.relative_residual = residual;
        if (residual <= options.tolerance) break;
        const double beta = rz_next / rz;
        rz = rz_next;
        split(n, threaded, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) p[i] = z[i] + beta * p[i];
        });
    }
    return true;
}

}  // namespace

Result<IndicatorValues> solve_cascadic(const PoissonOctree& tree, const OrientedSamples& samples,
                                       const SolverOptions& options, std::vector<LevelSolveStats>* stats) {
    auto start = std::chrono::steady_clock::now();
    // the levels' neighbour tables, shared by the right-hand side and each level's system (built once: they are the
    // largest arrays of a level after its key sets)
    const bool threaded = options.threads != 1;
    std::vector<StencilRows> rows;
    rows.reserve(tree.levels.size());
    for (const OctreeLevel& level : tree.levels) rows.push_back(StencilRows::build(level, threaded));
    std::vector<std::vector<double>> rhs = divergence_rhs(tree, samples, rows, threaded);
    IndicatorValues out;
    out.values.resize(tree.levels.size());
    out.at_samples.assign(samples.positions.size(), 0.0);
    std::vector<double> x, correction_at_samples;
    for (std::size_t li = 0; li < tree.levels.size(); ++li) {
        if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "poisson: cancelled while solving");
        const OctreeLevel& level = tree.levels[li];
        const LevelSystem system(tree, level.depth, samples, options.alpha, options.dirichlet, std::move(rows[li]),
                                 threaded);

        // the coarser levels' function on this level's grid
        std::vector<double>& values = out.values[li];
        if (li == 0)
            values.assign(level.support_vertices.size(), 0.0);
        else
            values = interpolate_to_finer(tree.levels[li - 1], out.values[li - 1], level, threaded);

        std::vector<double> b = std::move(rhs[li]);  // each level's right-hand side is used once
        if (li > 0) {
            system.subtract_stiffness(values, b);
            system.subtract_screening(out.at_samples, b);
        }

        LevelSolveStats level_stats;
        level_stats.depth = level.depth;
        level_stats.dofs = system.size();
        level_stats.assembly_seconds = seconds_since(start);
        start = std::chrono::steady_clock::now();
        if (!conjugate_gradients(system, b, options, x, level_stats))
            return make_error(ErrorCode::Cancelled, "poisson: cancelled while solving");

        // add this level's hats to the values and to chi at the samples
        SortedCursor cursor(level.support_vertices.keys);  // the dofs are support vertices, both lists sorted
        for (std::size_t v = 0; v < x.size(); ++v) {
            const std::uint32_t s = cursor.seek(level.dofs.keys[v]);
            if (x[v] != 0) values[s] += x[v];
        }
        system.evaluate_at_samples(x, correction_at_samples);
        for (std::size_t i = 0; i < correction_at_samples.size(); ++i) out.at_samples[i] += correction_at_samples[i];
        level_stats.solve_seconds = seconds_since(start);
        if (stats) stats->push_back(level_stats);
        start = std::chrono::steady_clock::now();
    }
    return out;
}

}  // namespace surfaced::reconstruct
