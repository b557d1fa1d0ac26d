// Quadratic error function of dual contouring: the point closest, in the least-squares sense, to a set of tangent
// planes (Hermite data: a point on the surface and the unit normal there). Private helper of mesh_field.
//
// Reference: T. Ju, F. Losasso, S. Schaefer, J. Warren, "Dual Contouring of Hermite Data", SIGGRAPH 2002, sec. 2.3
//            (solve around the mass point, truncate small singular values so that flat and cylindrical regions do
//            not pull the vertex away from the data).
#pragma once

#include "geometry/core/types.h"

namespace surfaced::implicit {

class Qef {
public:
    //! Adds the plane through `point` with unit normal `normal`. A non-finite or zero normal adds the point to the
    //! mass point only.
    void add(const Vec3& point, const Vec3& normal);

    //! Replaces the mass point (the origin of solve()) by `point`, after the planes have been added; later add()s
    //! average in as usual.
    void set_mass_point(const Vec3& point) { point_sum_ = point * static_cast<double>(count_); }

    //! The mean of the added points (the fallback vertex position).
    Vec3 mass_point() const;
    int count() const { return count_; }
    int planes() const { return planes_; }

    //! Minimiser of sum (n_i . (x - p_i))^2 closest to the mass point: eigen-decomposition of A^T A (Jacobi),
    //! eigenvalues below `relative_threshold` * the largest treated as zero. `rank` receives the number kept (0..3).
    //! At most `max_rank` eigen-directions are used (the largest): a lower rank trades a feature for a point
    //! nearer the data (mesh_field uses it when the full solution lies outside the cell).
    Vec3 solve(double relative_threshold, int* rank = nullptr, int max_rank = 3) const;

    //! The minimiser within the box [lo, hi]: the unconstrained solve() when it lies inside, else the best of the
    //! minimisers restricted to each face, edge and corner of the box (the active-set enumeration of the
    //! box-constrained least-squares problem), by error().
    Vec3 solve_in_box(double relative_threshold, const Vec3& lo, const Vec3& hi) const;

    //! sum (n_i . (x - p_i))^2 at x.
    double error(const Vec3& x) const;

private:
    //! Minimiser with the coordinates in `fixed_mask` (bit per axis) held at those of x0, the others starting from
    //! x0 (pseudo-inverse step; eigenvalues below threshold * `largest` dropped).
    Vec3 solve_fixed(int fixed_mask, const Vec3& x0, double threshold, double largest) const;

    // symmetric A^T A, A^T b, b^T b
    double a00_ = 0, a01_ = 0, a02_ = 0, a11_ = 0, a12_ = 0, a22_ = 0;
    Vec3 atb_{};
    double btb_ = 0;
    Vec3 point_sum_{};
    int count_ = 0;
    int planes_ = 0;
};

//! Eigen-decomposition of the symmetric 3x3 matrix m (row-major, m[i][j] == m[j][i]) by cyclic Jacobi rotations:
//! values[k] with eigenvector column vectors[.][k].
void symmetric_eigen3(const double m[3][3], double values[3], double vectors[3][3]);

}  // namespace surfaced::implicit
