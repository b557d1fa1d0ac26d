// Exact evaluation of the Catmull-Clark or Loop limit surface at any parametric point (face, u, v) of the base mesh.
//
// Method (Catmull-Clark). The limit surface over a quad whose corners are regular is a bicubic uniform B-spline
// patch of its 16 surrounding points (Stam 1998 for the smooth case). "Regular" here: every corner is either
//  * smooth: interior, four quads, no sharp edge, no vertex sharpness;
//  * on a crease: the face has exactly one of its two edges at the corner infinitely sharp (a boundary edge, or an
//    infinitely sharp crease), the corner has exactly two sharp edges, both infinite, and the face's side of the
//    crease holds two quads; the points beyond the sharp edge are phantoms, 2 P(crease) - P(inner), so that the
//    patch is the boundary B-spline (the crease rules are the B-spline rules with those phantoms);
//  * a corner: both of the face's edges at it infinitely sharp and the vertex follows the corner rule (infinite
//    vertex sharpness, or three or more infinitely sharp edges): phantoms on both sides.
// Method (Loop). Over a triangle whose corners are regular the limit surface is the quartic box spline of the 12
// points of the corners' 1-rings (Stam, "Evaluation of Loop subdivision surfaces", 1998; loop_patch.h). Regular
// corners: smooth valence 6; or on a straight infinitely sharp crease or boundary (two infinite sharp edges, three
// triangles on the face's side), with phantom points reflected through the crease line, which reproduce the crease
// rules exactly. Corners (the corner rule), darts and other valences are irregular.
// Anywhere else (extraordinary vertices, non-quads, semi-sharp features, darts, crease vertices with other
// sectors, faces that use a vertex twice) the face's 2-ring is refined locally with the same rules and options as
// subdivide() (interpolate.h, creases.h: one step of the scheme, so the child faces' 2-rings are exact), the child
// face containing the point is taken with its re-mapped parameter, and this repeats until the child is regular.
// Semi-sharp sharpness decays by at least one per level, so isolation ends after ceil(sharpness) levels near it;
// only a point converging on an irregular vertex descends further, up to `max_level`.
//
// Parameterization (OpenSubdiv Bfr's, so that (face, u, v) names the same point as Bfr::Surface::Evaluate):
//  * quads: the unit square, corner 0 at (0, 0), corner 1 at (1, 0), corner 2 at (1, 1), corner 3 at (0, 1);
//  * N-gons (N != 4): Bfr's quad sub-faces. Sub-face i (the Catmull-Clark child at corner i) is the tile
//    [x, x + 1/2] x [y, y + 1/2] with x = i % D, y = i / D, D = (N < 10 ? 2 + (N > 4) : 1 + floor(sqrt(N - 1)));
//    corner i sits at (x, y), the midpoint of edge i (towards corner i + 1) at (x + 1/2, y), the face centre at
//    (x + 1/2, y + 1/2) and the midpoint of edge i - 1 at (x, y + 1/2). Derivatives are with respect to (u, v).
//  * Loop triangles: u, v >= 0, u + v <= 1, corner 0 at (0, 0), corner 1 at (1, 0), corner 2 at (0, 1). Child j < 3
//    is the half-size triangle at corner j; child 3, the middle one, is turned half round (its corner 0 at
//    (1/2, 1/2)), so its local derivatives change sign.
//
// Exactness. Wherever the descent reaches a regular patch (everywhere except within 2^-max_level of an irregular
// vertex) the result is the exact limit position and exact first and second derivatives, up to rounding: measured
// against Bfr and Far, 4e-16 of the bounding diagonal for positions, 6e-14 for first and 2e-10 for second derivatives
// on every regression shape (Loop and Catmull-Clark alike; tests/geometry/*limit_evaluation_test.cpp). Within
// 2^-max_level of an irregular vertex (LimitSample::exact false) the position is the bilinear (Loop: linear) blend of
// the limit positions (OpenSubdiv's limit masks, limit.h) at the corners of the last face, which is exact at the vertex
// itself and elsewhere off by up to a fraction of that face's size (the parameterization is not linear at an
// extraordinary vertex; the face shrinks by the subdominant eigenvalue per level, about 0.45 at a valence-5 Loop
// vertex: measured 5e-11 of the diagonal on the icosahedron with max_level 24); first derivatives are the last face's
// corner differences scaled to (u, v) (the parametric derivative of a subdivision surface is not defined at an
// extraordinary vertex: it vanishes or diverges with the valence), second derivatives zero, and the normal at the
// vertex itself is the limit-mask normal. A point exactly at an irregular vertex is answered that way as soon as the
// vertex's sharpness has decayed, without descending further: exact position and normal, `exact` false. Darts (one
// sharp edge at a vertex) are the exception: the smooth limit mask does not model the sharp edge's crease rule, so
// the mask there is off by a fraction of its ring (0.0126 on catmark_inf_crease0 at level 0, as in OpenSubdiv's Far,
// whose limit at that vertex moves towards ours level by level); a point at a dart descends to `max_level`, and so
// does a point at a smooth Catmull-Clark vertex of valence 2 (faces glued back to back), whose mask in limit.h and
// in OpenSubdiv's Sdc is the corner mask (the vertex itself) while the surface converges elsewhere. (At an
// extraordinary Loop boundary vertex the crease rules leave no tangent plane: the limit-mask normal there is
// subdivide()'s, and Far's differs from it.) OpenSubdiv 3.5 and 3.6 give Loop second derivatives the wrong sign on
// sub-patches turned half round an odd number of times (they scale them by -4^depth); ours are the derivatives of
// the first ones, which the tests check by differences.
//
// Cost. Creation: one pass over the mesh (topology, sharpness, vertex-face lists) and the 16 (Loop: 12) control
// points of every regular base face. Evaluation on a regular base face: one bicubic (Loop: quartic box-spline)
// evaluation, about a hundred (Loop: two hundred) multiply-adds.
// Elsewhere: one local refinement of a few dozen faces per level descended (about ten microseconds); a random point
// on a face next to an extraordinary vertex needs about two levels on average, a point at distance d from it about
// log2(1/d). For many points on one face, face_surface() prepares the patches of its regular sub-faces once
// (LimitFaceSurface, the role of OpenSubdiv's Bfr::Surface), after which nearly every point is one patch evaluation.
//
// Any mesh subdivide() takes, under either scheme: non-manifold edges and vertices, and faces that use a vertex twice
// (irregular: refined, as OpenSubdiv does), included; Loop needs triangles (NotTriangleMesh otherwise, as
// subdivide()). Thread-safe: evaluate() is const and keeps no state between calls.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/subdivision/subdivide.h"

namespace surfaced {

//! One point of the limit surface and its derivatives with respect to the face's (u, v).
struct LimitSample {
    Vec3 position;
    Vec3 du, dv;
    Vec3 normal;         //!< normalize(du x dv); the limit-mask normal exactly at an irregular vertex; 0 if degenerate
    Vec3 duu, duv, dvv;  //!< only when asked for (zero otherwise, and when exact is false)
    int level = 0;       //!< local refinement levels descended to reach the point's patch
    bool exact = true;   //!< false: at an irregular vertex or within 2^-max_level of one (see the header)
};

struct LimitEvaluationOptions {
    //! Deepest local refinement; >= 12 (every semi-sharp feature has decayed by then) and <= 40.
    int max_level = 24;
};

class LimitFaceSurface;

//! The Catmull-Clark or Loop limit surface of one mesh under one SubdivisionOptions (scheme, boundary mode, crease
//! method, triangle rule, Loop weights, use of the mesh tags; `levels`, `limit_surface` and the UV options do not matter here). Copies share
//! the prepared data (immutable).
class LimitSurfaceEvaluator {
public:
    //! Validates the mesh as subdivide() does (NotTriangleMesh for a non-triangle under Loop, naming the face);
    //! InvalidArgument for max_level out of range.
    static Result<LimitSurfaceEvaluator> create(const PolygonMesh& mesh, const SubdivisionOptions& options,
                                                const LimitEvaluationOptions& evaluation = {});

    //! The limit surface at (u, v) of base face `face`. IndexOutOfRange (face), NonFinite (u or v), InvalidArgument
    //! ((u, v) outside the face's domain, or the face is a hole: holes have no limit surface).
    Result<LimitSample> evaluate(std::size_t face, double u, double v, bool second_derivatives = false) const;

    //! The surface over `face` prepared to `levels` local refinements (0..max_level; 6 leaves about 4^-6 of the
    //! face's area per irregular corner to the descent). Errors as evaluate() for the face.
    Result<LimitFaceSurface> face_surface(std::size_t face, int levels = 6) const;

    std::size_t face_count() const;
    //! Whether `face` (< face_count()) is a hole: it has no limit surface.
    bool is_hole(std::size_t face) const;
    //! The scheme the evaluator was created for.
    SubdivisionScheme scheme() const;
    //! The deepest local refinement (LimitEvaluationOptions::max_level).
    int max_level() const;

    struct Data;  //!< the base level, its sharpness, vertex-face lists and regular patches (limit_evaluation.cpp)

private:
    friend class LimitFaceSurface;
    LimitSurfaceEvaluator() = default;
    //! Checks (face, u, v) and returns where the descent starts: the N-gon's sub-face (or -1 for a quad) and the
    //! local coordinates in it.
    struct Start {
        int subface;
        double s, t;
    };
    Result<Start> locate(std::size_t face, double u, double v) const;

    std::shared_ptr<const Data> data_;
};

//! The limit surface over one base face, prepared for many evaluations (Bfr::Surface's role): the bicubic patches of
//! its regular sub-faces down to a number of local refinements, so that evaluating a point there is one patch
//! evaluation. A point closer to an irregular vertex than the prepared levels reach resumes the evaluator's descent
//! from the local refinement kept at its leaf; results are the evaluator's either way (bit for bit). Shares its
//! evaluator's data.
class LimitFaceSurface {
public:
    //! As LimitSurfaceEvaluator::evaluate on this face.
    Result<LimitSample> evaluate(double u, double v, bool second_derivatives = false) const;
    std::size_t patch_count() const { return patches_.size(); }

    //! A leaf of the prepared tree: the square [u0, u0 + size] x [v0, v0 + size] of the face's (u, v) domain, `level`
    //! refinements below the base face, and the bicubic uniform B-spline control points of the limit surface over it
    //! (4 x 4, u varying fastest, as evaluate_patch takes them), or null where the surface there is not one patch down
    //! to the prepared levels (next to an irregular vertex or an undecayed semi-sharp feature).
    struct Leaf {
        double u0 = 0, v0 = 0, size = 1;
        int level = 0;
        const std::array<Vec3, 16>* bspline = nullptr;
        std::int32_t node = -1;  //!< its node in nodes(); -1 for an N-gon's sub-face when the face is not prepared
    };
    //! Every leaf down to `max_level` (Catmull-Clark surfaces; a Loop surface's patches are triangles: none listed) (a node at max_level that has children is a leaf without a patch there),
    //! covering the face's domain once (an N-gon's leaves lie in its quad sub-faces' tiles).
    std::vector<Leaf> leaves(int max_level = 1 << 30) const;

    //! Points whose convex hull holds the limit surface over `leaf` (one of leaves()): for a leaf without a patch,
    //! the points of the local refinement kept there (or of the base face's neighbourhood when none is kept); every
    //! Catmull-Clark and Loop rule (smooth, crease, corner, fractional, triangle) is a convex combination, so each
    //! refinement keeps the surface inside the previous points' hull. Empty for a leaf with a patch.
    std::vector<Vec3> hull_points(const Leaf& leaf) const;

    struct Node {
        std::int32_t patch = -1;        //!< a regular sub-face: index into patches_
        std::int32_t first_child = -1;  //!< its sub-faces' nodes (4; the face's size for an N-gon's root)
    };

    //! The prepared tree, for callers that bound the surface (adaptive_tessellation.h). Node 0 is the face; a quad
    //! node's children are its quarters in corner order ((s, t) in [0, 1/2]^2, then +s, then both, then +t); an
    //! N-gon root's children are its sub-faces in corner order. A node with a patch is a leaf whose surface is that
    //! bicubic B-spline patch; a leaf without one was not resolved within the prepared levels.
    const std::vector<Node>& nodes() const { return nodes_; }
    //! Control points of patch i of uniform bicubic B-spline over its node's local (s, t) in [0, 1]^2: point
    //! (row r, column c) is [4 r + c], c along s, r along t.
    const std::array<Vec3, 16>& patch_points(std::size_t i) const { return patches_[i]; }

    struct Unresolved;  //!< the local refinements kept at the leaves without a patch (limit_evaluation.cpp)

private:
    friend class LimitSurfaceEvaluator;
    LimitSurfaceEvaluator owner_;
    std::size_t face_ = 0;
    std::vector<Node> nodes_;  //!< node 0: the face
    std::vector<std::array<Vec3, 16>> patches_;
    std::shared_ptr<const Unresolved> unresolved_;  //!< null when every leaf has a patch
};

}  // namespace surfaced
