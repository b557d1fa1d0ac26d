// The solved indicator function chi as an implicit::Field, for point queries and the implicit meshers:
// f(p) = chi(p) - iso_value, so f < 0 inside and normals towards f > 0 point away from the sampled solid. The
// reconstruction itself meshes chi with extract_surface.h, which needs no dense grid.
#pragma once

#include "geometry/implicit/field.h"
#include "geometry/reconstruct/octree.h"
#include "geometry/reconstruct/solver.h"

namespace surfaced::reconstruct {

//! Evaluates chi on the finest octree level whose support cells contain the point: chi is trilinear there (every
//! hat of that level and of the coarser ones is), so the value is exact and the gradient is the interpolant's
//! derivative. Cost: one hash lookup per level descended plus eight. Points outside the cube are clamped onto it.
//! References `tree` and `values`, which must outlive the field.
class IndicatorField final : public implicit::Field {
public:
    //! `origin` and `size`: the cube mapped onto the unit cube of the octree.
    IndicatorField(const PoissonOctree& tree, const IndicatorValues& values, const Vec3& origin, double size,
                   double iso_value);

    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    //! chi is a smoothed step, far from a distance: only its sign is meaningful.
    implicit::FieldKind kind() const override { return implicit::FieldKind::General; }
    double lipschitz() const override;

private:
    //! The level index and cell whose trilinear interpolant gives chi at q (unit coordinates), and its corners.
    void locate(const Vec3& q, std::size_t& level, double corners[8]) const;
    Vec3 to_unit(const Vec3& p) const;

    const PoissonOctree& tree_;
    const IndicatorValues& values_;
    Vec3 origin_;
    double size_;
    double iso_;
};

}  // namespace surfaced::reconstruct
