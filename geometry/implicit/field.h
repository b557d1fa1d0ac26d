// The one interface between implicit-surface descriptions (scenes, expressions, level-set grids, fractals) and what
// is done with them (queries, sphere tracing, meshing). Convention: the surface is f = 0, f < 0 inside, f > 0 outside.
#pragma once

#include "geometry/core/types.h"

namespace surfaced::implicit {

//! What a field's value promises about the distance to its zero set.
enum class FieldKind {
    ExactDistance,  //!< |f(p)| is the Euclidean distance to the surface (sphere, box, translated/rotated ones, ...)
    DistanceBound,  //!< |f(p)-f(q)| <= lipschitz()*|p-q|, hence |f(p)|/lipschitz() <= distance (CSG, blends, level sets)
    General,        //!< only the sign is meaningful (algebraic expressions); lipschitz() is an estimate or +inf
};

//! A scalar field f: R^3 -> R. Implementations are immutable after construction and safe to evaluate from several
//! threads at once.
class Field {
public:
    virtual ~Field() = default;

    virtual double value(const Vec3& p) const = 0;

    //! ∇f at p. The default is a central difference with step h = 1e-6 * (1 + |p|); exact fields override it.
    virtual Vec3 gradient(const Vec3& p) const {
        const double h = 1e-6 * (1.0 + norm(p));
        const Vec3 dx{h, 0, 0}, dy{0, h, 0}, dz{0, 0, h};
        return Vec3{value(p + dx) - value(p - dx), value(p + dy) - value(p - dy), value(p + dz) - value(p - dz)} *
               (0.5 / h);
    }

    virtual FieldKind kind() const = 0;

    //! A bound L with |f(p) - f(q)| <= L |p - q| (1 for exact distances). Sphere tracing steps |f| / L.
    virtual double lipschitz() const { return 1.0; }
};

}  // namespace surfaced::implicit
