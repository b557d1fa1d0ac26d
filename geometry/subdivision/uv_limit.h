// The limit of a mesh's texture coordinates at a parametric point (face, u, v): the face-varying counterpart of
// LimitSurfaceEvaluator (limit_evaluation.h), with the same (face, u, v) parameterization (OpenSubdiv Bfr's).
//
// Method. subdivide() refines the UVs on a "value mesh" of their own (face_varying.h): the mesh's faces over one
// vertex per distinct (vertex, UV) pair, so that seams are its boundaries, with the mesh's sharpness plus what the
// uv_interpolation rule makes sharp. That value mesh, with its sharpness as crease and corner tags, is a mesh whose
// Catmull-Clark limit surface is the limit of the UVs, so the UVs are evaluated as LimitSurfaceEvaluator evaluates
// positions (exact, with the same exactness near irregular vertices). "all" is bilinear: the UVs at the face's corners
// blended bilinearly on quads, and on each quad sub-face of an N-gon (corner, edge midpoints, centroid).
//
// Dependent sharpness. With corners-plus1 and corners-plus2, a UV at a vertex with two UV regions, exactly one of
// which has semi-sharp edges inside it, follows OpenSubdiv's "dependent sharpness" (face_varying.h UvOverride): a
// corner until its sibling's edges have decayed, then a crease with their fractional weight. When one of those edges
// decays last and its sharpness at the vertex drops by one per level (uniform creasing, or Chaikin's with a single
// semi-sharp edge there), that is exactly a vertex sharpness of the value mesh, and it is evaluated so.
//
// Approximation. Otherwise (several edges decaying at the same last level, or Chaikin's with several semi-sharp
// edges) the value is evaluated by the value mesh's own rule (a smooth boundary value) and the faces using it are
// reported inexact (UvSample::exact false). Measured against Bfr's face-varying surface (tests/geometry/
// uv_limit_test.cpp, UVs jittered by 0.05 on a fan of extent 1.5): at most 7e-3 in UV on those faces. Nothing else
// is approximated: every mode matches Bfr to 1e-15 on OpenSubdiv's face-varying shapes.
//
// Catmull-Clark only, as LimitSurfaceEvaluator. Thread-safe (const, no state between calls).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/subdivision/subdivide.h"

namespace surfaced {

//! Whether (u, v) is in the parameter domain of a face with `face_size` corners (Bfr's: the unit square for a quad,
//! the N quad sub-face tiles of an N-gon; limit_evaluation.h). u and v finite.
bool limit_domain_contains(std::size_t face_size, double u, double v);

struct UvSample {
    Vec2 uv;
    bool exact =
        true;  //!< false near an irregular value (as LimitSample::exact) or on a face with an approximated value
};

class UvFaceSurface;

//! The limit of the texture coordinates of one mesh under one SubdivisionOptions (as LimitSurfaceEvaluator; the
//! uv_interpolation rule matters here).
class UvLimitEvaluator {
public:
    //! InvalidArgument when the mesh has no UVs; otherwise the errors of LimitSurfaceEvaluator::create.
    static Result<UvLimitEvaluator> create(const PolygonMesh& mesh, const SubdivisionOptions& options,
                                           const LimitEvaluationOptions& evaluation = {});

    //! The UVs' limit at (u, v) of base face `face`; errors as LimitSurfaceEvaluator::evaluate.
    Result<UvSample> evaluate(std::size_t face, double u, double v) const;
    //! The face prepared for many evaluations (LimitSurfaceEvaluator::face_surface on the value mesh).
    Result<UvFaceSurface> face_surface(std::size_t face, int levels = 6) const;

    //! Faces using a value the rule above approximates (their samples are inexact).
    std::size_t approximated_face_count() const;

private:
    friend class UvFaceSurface;
    UvLimitEvaluator() = default;
    Result<UvSample> bilinear(std::size_t face, double u, double v) const;

    //! The value mesh's limit surface; unset with "all" (bilinear).
    std::optional<LimitSurfaceEvaluator> values_;
    //! "all": each face's corner UVs (face_offsets as the mesh's).
    std::vector<Index> face_offsets_;
    std::vector<Vec2> corner_uvs_;
    std::vector<std::uint8_t> approximated_;  //!< per face
};

//! One face's UV limit prepared for many evaluations.
class UvFaceSurface {
public:
    Result<UvSample> evaluate(double u, double v) const;

private:
    friend class UvLimitEvaluator;
    const UvLimitEvaluator* owner_ = nullptr;
    std::size_t face_ = 0;
    std::optional<LimitFaceSurface> surface_;
};

}  // namespace surfaced
