// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations (Golub & Van Loan, Matrix Computations,
// 4th ed., section 8.5). Robust for repeated and zero eigenvalues, which covariance matrices of flat or degenerate
// neighbourhoods have; converges quadratically, so a handful of sweeps reach machine precision.
#pragma once

#include <array>
#include <cmath>

#include "geometry/core/types.h"

namespace surfaced {

struct SymmetricEigen3 {
    std::array<double, 3> values{};  //!< ascending
    std::array<Vec3, 3> vectors{};   //!< unit, orthogonal; vectors[i] belongs to values[i]
};

//! Precondition: `a` is symmetric and finite.
inline SymmetricEigen3 symmetric_eigen3(const std::array<std::array<double, 3>, 3>& a_in) {
    std::array<std::array<double, 3>, 3> a = a_in;
    std::array<std::array<double, 3>, 3> v{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-30 * diag || off == 0.0) break;
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0.0) continue;
                // rotation angle that zeroes a[p][q] (the smaller of the two solutions, for stability)
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0);
                const double s = t * c;
                for (int k = 0; k < 3; ++k) {  // A <- A J
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {  // A <- J^T A
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {  // V <- V J
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }
    SymmetricEigen3 out;
    std::array<int, 3> order{0, 1, 2};
    for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j)
            if (a[order[j]][order[j]] < a[order[i]][order[i]]) std::swap(order[i], order[j]);
    for (int i = 0; i < 3; ++i) {
        const int c = order[static_cast<std::size_t>(i)];
        out.values[static_cast<std::size_t>(i)] = a[c][c];
        out.vectors[static_cast<std::size_t>(i)] = Vec3{v[0][c], v[1][c], v[2][c]};
    }
    return out;
}

}  // namespace surfaced
