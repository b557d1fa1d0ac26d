#include "geometry/implicit/qef.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace surfaced::implicit {

void Qef::add(const Vec3& point, const Vec3& normal) {
    point_sum_ += point;
    ++count_;
    const double len = norm(normal);
    if (!(len > 0) || !std::isfinite(len)) return;
    const Vec3 n = normal * (1.0 / len);
    const double b = dot(n, point);
    a00_ += n.x * n.x;
    a01_ += n.x * n.y;
    a02_ += n.x * n.z;
    a11_ += n.y * n.y;
    a12_ += n.y * n.z;
    a22_ += n.z * n.z;
    atb_ += n * b;
    btb_ += b * b;
    ++planes_;
}

Vec3 Qef::mass_point() const { return count_ > 0 ? point_sum_ * (1.0 / count_) : Vec3{}; }

double Qef::error(const Vec3& x) const {
    const Vec3 ax{a00_ * x.x + a01_ * x.y + a02_ * x.z, a01_ * x.x + a11_ * x.y + a12_ * x.z,
                  a02_ * x.x + a12_ * x.y + a22_ * x.z};
    return std::max(0.0, dot(x, ax) - 2 * dot(x, atb_) + btb_);
}

void symmetric_eigen3(const double m[3][3], double values[3], double vectors[3][3]) {
    double a[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            a[i][j] = m[i][j];
            vectors[i][j] = i == j ? 1.0 : 0.0;
        }
    for (int sweep = 0; sweep < 32; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-30 * diag || off == 0) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0) continue;
                // rotation that zeroes a[p][q] (Golub & Van Loan, sym.schur2)
                const double tau = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                const double t = (tau >= 0 ? 1.0 : -1.0) / (std::fabs(tau) + std::sqrt(1 + tau * tau));
                const double c = 1 / std::sqrt(1 + t * t), s = t * c;
                for (int k = 0; k < 3; ++k) {  // a = a * J
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {  // a = J^T * a
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double vkp = vectors[k][p], vkq = vectors[k][q];
                    vectors[k][p] = c * vkp - s * vkq;
                    vectors[k][q] = s * vkp + c * vkq;
                }
            }
    }
    for (int i = 0; i < 3; ++i) values[i] = a[i][i];
}

Vec3 Qef::solve(double relative_threshold, int* rank, int max_rank) const {
    const Vec3 c = mass_point();
    if (rank) *rank = 0;
    if (planes_ == 0) return c;
    const double m[3][3] = {{a00_, a01_, a02_}, {a01_, a11_, a12_}, {a02_, a12_, a22_}};
    double values[3], vectors[3][3];
    symmetric_eigen3(m, values, vectors);
    const double largest = std::max({std::fabs(values[0]), std::fabs(values[1]), std::fabs(values[2])});
    if (!(largest > 0)) return c;
    // x = c + pinv(A^T A) (A^T b - A^T A c)
    const Vec3 ac{a00_ * c.x + a01_ * c.y + a02_ * c.z, a01_ * c.x + a11_ * c.y + a12_ * c.z,
                  a02_ * c.x + a12_ * c.y + a22_ * c.z};
    const Vec3 r = atb_ - ac;
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int p, int q) { return values[p] > values[q]; });
    Vec3 x = c;
    int kept = 0;
    for (int k : order) {
        if (values[k] < relative_threshold * largest || kept >= max_rank) continue;
        const Vec3 v{vectors[0][k], vectors[1][k], vectors[2][k]};
        x += v * (dot(v, r) / values[k]);
        ++kept;
    }
    if (rank) *rank = kept;
    return is_finite(x) ? x : c;
}

Vec3 Qef::solve_fixed(int fixed_mask, const Vec3& x0, double threshold, double largest) const {
    double m[3][3] = {{a00_, a01_, a02_}, {a01_, a11_, a12_}, {a02_, a12_, a22_}};
    const Vec3 ax{a00_ * x0.x + a01_ * x0.y + a02_ * x0.z, a01_ * x0.x + a11_ * x0.y + a12_ * x0.z,
                  a02_ * x0.x + a12_ * x0.y + a22_ * x0.z};
    Vec3 r = atb_ - ax;
    for (int a = 0; a < 3; ++a)
        if (fixed_mask >> a & 1) {
            r[a] = 0;
            for (int b = 0; b < 3; ++b) m[a][b] = m[b][a] = 0;
        }
    double values[3], vectors[3][3];
    symmetric_eigen3(m, values, vectors);
    Vec3 x = x0;
    for (int k = 0; k < 3; ++k) {
        if (!(values[k] >= threshold * largest) || values[k] <= 0) continue;
        const Vec3 v{vectors[0][k], vectors[1][k], vectors[2][k]};
        x += v * (dot(v, r) / values[k]);
    }
    for (int a = 0; a < 3; ++a)
        if (fixed_mask >> a & 1) x[a] = x0[a];  // exactly, whatever the rounding of the rotations
    return x;
}

Vec3 Qef::solve_in_box(double relative_threshold, const Vec3& lo, const Vec3& hi) const {
    auto inside = [&](const Vec3& x) {
        for (int a = 0; a < 3; ++a) {
            const double slack = 1e-9 * (hi[a] - lo[a]);
            if (!(x[a] >= lo[a] - slack && x[a] <= hi[a] + slack)) return false;
        }
        return true;
    };
    const Vec3 free_solution = solve(relative_threshold);
    if (inside(free_solution) || planes_ == 0) return free_solution;
    const double largest = std::max({a00_ + a11_ + a22_, 0.0});  // >= the largest eigenvalue (trace)
    const Vec3 c = mass_point();
    Vec3 best = c;
    double best_error = std::numeric_limits<double>::infinity();
    // faces (one coordinate fixed), edges (two), corners (three)
    for (int mask = 1; mask < 8; ++mask)
        for (int sides = 0; sides < 8; ++sides) {
            if ((sides & ~mask) != 0) continue;
            Vec3 x0 = c;
            for (int a = 0; a < 3; ++a)
                if (mask >> a & 1) x0[a] = (sides >> a & 1) ? hi[a] : lo[a];
            const Vec3 x = solve_fixed(mask, x0, relative_threshold, largest);
            if (!is_finite(x) || !inside(x)) continue;
            const double e = error(x);
            if (e < best_error) {
                best_error = e;
                best = x;
            }
        }
    return best;
}

}  // namespace surfaced::implicit
