// Tessellation of the Catmull-Clark limit surface to a distance tolerance (the role of OpenSubdiv's
// Bfr::Tessellation, with segment rates chosen from bounds on the surface instead of given).
//
// Domains. Every base face that is not a hole is tessellated in its own parameterization (limit_evaluation.h): a quad
// is one domain, the unit square; an N-gon is N domains, its quad sub-faces, each tessellated as a quad. A domain has
// an inner grid (nu x nv segments, its lines uniform or graded: spaced where the surface needs them) and points on
// each of its four sides. A side is a base edge (a quad's) or half of one (an N-gon's, whose midpoint is then a
// vertex) or a spoke of an N-gon (from an edge midpoint to the centre). The points along a base edge (each half of
// an N-gon's edge) and along a spoke are graded once, by a density per 1/32 of its length that is the largest any
// domain on it needs there (its inner grid's density along that direction, raised where its transition strip
// fails), so that an edge running into a crease is fine only at that end; the vertices on an edge are evaluated
// once and shared by index by every face on it, so the output is watertight where the input is closed and has no
// T-junctions. A uniform domain whose sides all carry its inner rates, uniformly, is a regular grid; otherwise its
// inner grid's points are joined to the sides by one transition strip per side (Bfr::Tessellation's layout). A grid
// is plain (each cell two right triangles) or staggered (odd rows at the midpoints of the s intervals, isosceles
// triangles, which meet a bound with about 0.78 times the points where the surface curves both ways), whichever the
// grading finds takes fewer triangles (tessellation_strips.h).
//
// Rates (guaranteed). The limit surface over a domain is a tree of bicubic B-spline patches (LimitFaceSurface, prepared
// to kTreeLevels local refinements) plus, at irregular vertices (and semi-sharp features not decayed by then), leaves
// without a patch. For a triangle T with parameter corners p_i and unit normal m (of the triangle of S at its corners),
// the distance from S(x) to T's plane is |m . (S(x) - sum l_i S(p_i))|, the linear interpolation error of the scalar m
// . S: at most (1/2) max_x sum l_i Q(p_i - x) (Taylor at x along the segments to the corners), with Q(d) = Muu du^2 + 2
// Muv |du dv| + Mvv dv^2 bounding m . S_ss, m . S_st, m . S_tt by the Bernstein coefficients, over the part of each
// patch the triangle's bounding box covers, of the patches' second-difference B-splines projected on m, scaled by
// 4^depth; the signs of m . S_ss and m . S_tt are kept apart (the error lies between the negative side's bound and the
// positive side's), so where the surface is saddle-shaped each side carries one direction's curvature only. Only the
// surface's bending away from the plane counts, not the parameterization's tangential non-uniformity (which a bound on
// |S(x) - T(x)| at equal parameters would). This is a guarantee (up to rounding) on the distance to the triangle's
// plane for every triangle that overlaps only patches; a point whose projection on that plane falls outside the
// triangle is next to a neighbour's, except beyond an open boundary: a triangle with an edge there is bounded on |S(x)
// - T(x)| (the full second derivatives). Each domain's grid lines are graded: densities per 1/32 of s and of t, started
// from each patch's second derivatives along its mean normal (an estimate, not a bound), raised where a triangle of
// the grid exceeds the tolerance (around a patch whose own bound fails, else over the triangle), so that a narrow band of
// high curvature (a semi-sharp crease) is fine only where it lies; a transition strip's failing triangle raises its
// edge's or spoke's density over the part of the side it spans (its other domains are checked again). Patches deeper
// than kBoundedDepth, and leaves without a patch (at irregular vertices, where the second derivatives grow without
// bound for valences above 4), are not bounded: a triangle that overlaps them is bounded over the rest and also checked
// by sampling: the distance from S(x) to the triangle's plane at the 25 non-corner points of a barycentric grid of step
// 1/6, evaluated exactly, must be at most tolerance / kSampledSafety. The sampled part is a measurement with a safety
// factor, not a guarantee. The reported error is the largest of the bounds and of the measured distances.
//
// Decimation (options.decimate, with guaranteed rates). A grid's lines span its domain, so the lines a narrow band
// needs also cross the rest of the face. After the output vertices are evaluated, the vertices the tolerance does not
// need are removed by half-edge collapses (tessellation_decimation.h), each accepted only when every triangle it
// creates passes the same bound (or sampled measurement) as the grids' triangles; a vertex on a base edge or spoke
// moves only along it, domain corners never move, so the output stays watertight and keeps its Euler characteristic.
//
// Output. Triangles, counter-clockwise as the base faces; per-vertex exact limit normals (normalize(du x dv), the
// limit-mask normal at an irregular vertex; a vertex on a crease takes the normal of the face that evaluated it);
// face-varying UVs when the mesh has them, bilinear in each domain's (s, t) between its corners' UVs (an N-gon's
// edge midpoints and centre take the averages of its corner UVs), which is not the subdivided UV layout.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/subdivision/limit_evaluation.h"

namespace surfaced {

//! Patches deeper than this in a domain (within 2^-kBoundedDepth of an irregular vertex or a semi-sharp feature)
//! are sampled rather than bounded.
inline constexpr int kBoundedDepth = 5;
//! Local refinements prepared per base face: the deepest bounded patches of an N-gon's sub-face domain (one level
//! below the face). Deeper parts are sampled, and evaluating there resumes the descent (exact either way).
inline constexpr int kTreeLevels = kBoundedDepth + 1;
//! Triangles at irregular vertices, which are sampled rather than bounded, must measure tolerance / kSampledSafety.
inline constexpr double kSampledSafety = 2.0;
//! LimitTessellationOptions::straddle's default: about the fewest triangles on the benchmark's shapes (0.35 to 0.55
//! give similar counts; above, the sides of a convex patch's bound that are not one-sided take over).
inline constexpr double kDefaultStraddle = 0.45;

struct LimitTessellationOptions {
    //! Largest allowed distance between the triangles and the limit surface (model units), finite and > 0.
    double tolerance = 1e-3;
    //! Ceiling on the segments of one base edge, spoke or domain direction (1..4096); more is BudgetExceeded.
    int max_segments = 256;
    //! Ceiling on the output triangles, checked from the rates before any output vertex is evaluated (0: none).
    std::uint64_t max_triangles = 0;
    //! true: graded rates from the bounds above (sampling only where no patch bounds the surface). false: uniform
    //! rates per domain from the measured distance of every triangle (25 points, within tolerance /
    //! kSampledSafety), no guarantee (docs/benchmarks.md compares them).
    bool guaranteed = true;
    //! With guaranteed rates: afterwards remove the vertices the tolerance does not need (bounded half-edge
    //! collapses, tessellation_decimation.h), so that lines a narrow band needs do not cross the rest of a face.
    bool decimate = true;
    //! With guaranteed rates: also grade each face as a staggered grid (tessellation_strips.h) and keep whichever
    //! layout takes fewer triangles; false: plain grids only.
    bool stagger = true;
    //! With guaranteed rates, 0 to below 1. Vertices move off the limit surface along the normal, towards its
    //! convex side, by straddle x tolerance where both principal curvatures have one sign (tessellation_bounds.h's
    //! straddle_offset; not on saddles, at irregular vertices, on infinitely sharp creases and corners or open
    //! boundaries), so that the surface crosses the triangles and the distance is split between both sides; the
    //! bound counts the offsets, so the surface stays within the tolerance of the triangles. 0: every vertex on the
    //! limit surface, where the triangles' distance to it lies on one side wherever it curves one way. The default
    //! takes 0.70 to 0.86 of the triangles of 0 on the benchmark's shapes at 1e-3 of their diagonal, 1.03 on one
    //! whose faces mostly lie along creases and saddles (docs/benchmarks.md).
    double straddle = kDefaultStraddle;
    //! 1: plan on the calling thread; anything else: prepare and grade the two halves of the faces on two threads
    //! (the faces' work is independent; the result is the same).
    int threads = 1;
    //! Polled between faces; when it fires the result is Cancelled.
    Cancel cancel;
};

//! The rates tessellate_limit follows. Computing it prepares each face's patch tree and evaluates the limit at the
//! points of the candidate layouts (for the triangles' planes) and at sample points of the triangles at irregular
//! vertices; the output is assembled afterwards. The grids a domain asks for only grow, so the budget
//! (max_triangles) is checked on them as they are made, before the next domain's work.
struct LimitTessellationPlan {
    struct Domain {
        std::uint32_t face = 0;
        std::int32_t subface = -1;   //!< -1: the quad itself; else the N-gon's sub-face (corner) index
        int nu = 1, nv = 1;          //!< inner rates
        int side[4] = {1, 1, 1, 1};  //!< segments on sides t = 0, s = 1, t = 1, s = 0
        //! Graded inner grid: its lines s = s_lines[i] (nu + 1 values from 0 to 1) and t = t_lines[j]; empty: the
        //! uniform i / nu, j / nv. A graded domain is always joined to its sides by transition strips.
        std::vector<double> s_lines, t_lines;
        //! Points of side k at fractions side_lines[k][i] along it (side[k] + 1 values from 0 to 1, in the side's
        //! direction: corner k to corner k + 1); empty: the uniform i / side[k]. They follow their base edge's or
        //! spoke's grading, the same for every domain on it.
        std::array<std::vector<double>, 4> side_lines;
        //! Odd rows at the midpoints of the s intervals (tessellation_strips.h), where that takes fewer triangles.
        bool staggered = false;
        double s_at(int i) const { return s_lines.empty() ? double(i) / nu : s_lines[std::size_t(i)]; }
        double t_at(int j) const { return t_lines.empty() ? double(j) / nv : t_lines[std::size_t(j)]; }
        double side_at(int k, int i) const {
            const auto& lines = side_lines[std::size_t(k)];
            return lines.empty() ? double(i) / side[k] : lines[std::size_t(i)];
        }
    };
    std::vector<Domain> domains;
    //! Segments per base edge (both halves of an N-gon's), in the order of first use by faces.
    std::vector<int> edge_rates;
    std::uint64_t triangles = 0;  //!< output triangle count before decimation (exact without it)
    std::uint64_t vertices = 0;   //!< output vertex count before decimation
    double error_bound = 0;       //!< largest true bound over the bounded triangles
    double sampled_error = 0;     //!< largest measured error over the sampled triangles
};

//! Errors: InvalidArgument (tolerance, max_segments), BudgetExceeded (a rate above max_segments, or more than
//! max_triangles), Cancelled, and the evaluator's errors for faces it cannot evaluate (Unsupported).
Result<LimitTessellationPlan> plan_limit_tessellation(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& base,
                                                      const LimitTessellationOptions& options);

//! The output triangle count of a plan (= plan.triangles; decimation only removes triangles), for budgets.
inline std::uint64_t predict_triangles(const LimitTessellationPlan& plan) { return plan.triangles; }

//! Where an output vertex lies: base face and its (u, v) (limit_evaluation.h's parameterization).
struct LimitSite {
    std::uint32_t face = 0;
    double u = 0, v = 0;
};

struct LimitTessellation {
    PolygonMesh mesh;
    std::vector<LimitSite> sites;         //!< per output vertex: the point of the limit surface it is
    std::vector<Index> face_of_triangle;  //!< base face each output triangle lies on
    LimitTessellationPlan plan;
    //! The largest bound and measured error over the output triangles (max(plan.error_bound, plan.sampled_error)
    //! without decimation).
    double achieved_error = 0;
    std::size_t removed_vertices = 0;  //!< by decimation: the output has plan.vertices minus these
};

//! `base` must be the mesh `evaluator` was created from. Plans, then evaluates each output vertex once.
Result<LimitTessellation> tessellate_limit(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& base,
                                           const LimitTessellationOptions& options);

}  // namespace surfaced
