#pragma once
// Our B-spline surfaces in OpenCASCADE's form, for the tests and benches that use OCCT as the reference (header-only:
// include it only from the translation units that already compile OCCT's headers).
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Pnt.hxx>

#include <vector>

#include "geometry/surfaces/bspline_surface.h"

namespace surfaced::testing {

//! A knot vector as OCCT takes it: the distinct values and their multiplicities (1-based arrays, resized here).
inline void occt_knots(const std::vector<double>& knots, TColStd_Array1OfReal& values, TColStd_Array1OfInteger& mults) {
    std::vector<double> v;
    std::vector<int> m;
    for (double k : knots) {
        if (!v.empty() && v.back() == k) {
            ++m.back();
        } else {
            v.push_back(k);
            m.push_back(1);
        }
    }
    values.Resize(1, static_cast<int>(v.size()), false);
    mults.Resize(1, static_cast<int>(v.size()), false);
    for (std::size_t i = 0; i < v.size(); ++i) {
        values.SetValue(static_cast<int>(i) + 1, v[i]);
        mults.SetValue(static_cast<int>(i) + 1, m[i]);
    }
}

//! The same surface as a Geom_BSplineSurface (non-periodic; OCCT reads an unclamped knot vector as ours does, the
//! domain being [U[p], U[nu]]); rational only when ours is.
inline Handle(Geom_BSplineSurface) to_occt_surface(const BSplineSurface& s) {
    TColgp_Array2OfPnt poles(1, s.count_u, 1, s.count_v);
    TColStd_Array2OfReal weights(1, s.count_u, 1, s.count_v);
    for (int j = 0; j < s.count_v; ++j)
        for (int i = 0; i < s.count_u; ++i) {
            const Vec3& p = s.at(i, j);
            poles.SetValue(i + 1, j + 1, gp_Pnt(p.x, p.y, p.z));
            weights.SetValue(i + 1, j + 1, s.weight(i, j));
        }
    TColStd_Array1OfReal ku(1, 1), kv(1, 1);
    TColStd_Array1OfInteger mu(1, 1), mv(1, 1);
    occt_knots(s.knots_u, ku, mu);
    occt_knots(s.knots_v, kv, mv);
    if (s.rational()) return new Geom_BSplineSurface(poles, weights, ku, kv, mu, mv, s.degree_u, s.degree_v);
    return new Geom_BSplineSurface(poles, ku, kv, mu, mv, s.degree_u, s.degree_v);
}

}  // namespace surfaced::testing
