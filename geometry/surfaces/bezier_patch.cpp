// Tensor-product Bézier patches. Evaluation is separable de Casteljau (geometry/curves/de_casteljau.h): u on each
// row of the control net, then v on the column of row results; derivatives come from the rows' hodographs.
//
// Tolerance bound (why tessellation_error_bound is a guarantee). For a triangle of the parameter grid with legs
// h = 1/nu and k = 1/nv, a point x of it with barycentric weights l_i, and the linear interpolant L of S at the
// triangle's corners p_i: S(p_i) = S(x) + DS(x)(p_i - x) + R_i with |R_i| <= (1/2)(Muu du_i^2 + 2 Muv |du_i dv_i|
// + Mvv dv_i^2). Since sum l_i (p_i - x) = 0, |L(x) - S(x)| = |sum l_i R_i|. The weighted variance of the corners'
// u coordinates is at most h^2/4 (one corner off the others by h), of v at most k^2/4, and by Cauchy-Schwarz the
// weighted mean of |du dv| at most hk/4. Hence |L - S| <= (1/8)(Muu h^2 + 2 Muv h k + Mvv k^2). The second partial
// derivatives are Bernstein combinations (convex) of the net's scaled second differences, so
// Muu <= m(m-1) max|D2u b|, Mvv <= n(n-1) max|D2v b|, Muv <= m n max|DuDv b| (Filip, Magedson, Markot 1986).
#include "geometry/surfaces/bezier_patch.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>

#include "geometry/curves/de_casteljau.h"

namespace surfaced {
namespace {

std::span<const Vec3> row(const BezierPatch& patch, int j) {
    return {patch.points.data() + static_cast<std::size_t>(j * patch.row_size()),
            static_cast<std::size_t>(patch.row_size())};
}

//! Size of the control net, the scale against which "du x dv vanishes" is judged.
double net_scale(const BezierPatch& patch) {
    Box3 box;
    for (const Vec3& p : patch.points) box.add(p);
    return box.diagonal();
}

//! |du x dv| scales like (net size)^2; below kVanishing times that it is rounding noise, not a direction.
constexpr double kVanishing = 1e-12;

Vec3 normalized(const Vec3& v) {
    const double length = norm(v);
    return length > 0 ? v * (1.0 / length) : Vec3{};
}

struct NetBounds {
    double uu = 0, uv = 0, vv = 0;  //!< bounds on |S_uu|, |S_uv|, |S_vv| over the patch
};

NetBounds second_derivative_bounds(const BezierPatch& patch) {
    const int m = patch.degree_u, n = patch.degree_v;
    double d2u = 0, d2v = 0, duv = 0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i + 2 <= m; ++i)
            d2u = std::max(d2u, norm(patch.at(i + 2, j) - 2.0 * patch.at(i + 1, j) + patch.at(i, j)));
    for (int j = 0; j + 2 <= n; ++j)
        for (int i = 0; i <= m; ++i)
            d2v = std::max(d2v, norm(patch.at(i, j + 2) - 2.0 * patch.at(i, j + 1) + patch.at(i, j)));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < m; ++i)
            duv = std::max(duv, norm(patch.at(i + 1, j + 1) - patch.at(i + 1, j) - patch.at(i, j + 1) + patch.at(i, j)));
    return {m * (m - 1) * d2u, m * n * duv, n * (n - 1) * d2v};
}

// ---- shared edges ---------------------------------------------------------------------------------------------

//! Edges of a patch, in this order: v = 0 and v = 1 (running along u), u = 0 and u = 1 (running along v).
enum EdgeSide { kEdgeV0 = 0, kEdgeV1 = 1, kEdgeU0 = 2, kEdgeU1 = 3 };

bool runs_along_u(int side) { return side == kEdgeV0 || side == kEdgeV1; }

std::vector<Vec3> edge_points(const BezierPatch& patch, int side) {
    std::vector<Vec3> out;
    if (runs_along_u(side)) {
        const int j = side == kEdgeV0 ? 0 : patch.degree_v;
        for (int i = 0; i <= patch.degree_u; ++i) out.push_back(patch.at(i, j));
    } else {
        const int i = side == kEdgeU0 ? 0 : patch.degree_u;
        for (int j = 0; j <= patch.degree_v; ++j) out.push_back(patch.at(i, j));
    }
    return out;
}

//! Bit pattern of a coordinate with -0 and +0 identified (adding +0.0 turns -0.0 into +0.0).
std::uint64_t coordinate_key(double x) {
    x += 0.0;
    std::uint64_t bits = 0;
    std::memcpy(&bits, &x, sizeof bits);
    return bits;
}

using PointKey = std::array<std::uint64_t, 3>;
PointKey point_key(const Vec3& p) { return {coordinate_key(p.x), coordinate_key(p.y), coordinate_key(p.z)}; }

struct PointKeyHash {
    std::size_t operator()(const PointKey& k) const {
        std::size_t h = 1469598103934665603ull;
        for (std::uint64_t w : k) h = (h ^ w) * 1099511628211ull;
        return h;
    }
};

//! An edge's control points in a direction both patches agree on (the lexicographically smaller of the two).
struct CanonicalEdge {
    std::vector<PointKey> key;
    std::vector<Vec3> points;  //!< in canonical order
    bool reversed = false;     //!< the patch runs along the edge opposite to the canonical order
    bool collapsed = false;    //!< all control points equal: the edge is a single point
};

CanonicalEdge canonical_edge(const BezierPatch& patch, int side) {
    CanonicalEdge edge;
    edge.points = edge_points(patch, side);
    for (const Vec3& p : edge.points) edge.key.push_back(point_key(p));
    std::vector<PointKey> reversed_key(edge.key.rbegin(), edge.key.rend());
    if (reversed_key < edge.key) {
        edge.key = std::move(reversed_key);
        std::reverse(edge.points.begin(), edge.points.end());
        edge.reversed = true;
    }
    edge.collapsed = std::all_of(edge.key.begin(), edge.key.end(), [&](const PointKey& k) { return k == edge.key[0]; });
    return edge;
}

//! Points of an edge at parameters k/segments, k = 0..segments, in the patch's own direction. Computed from the
//! canonical control points at canonical parameters, so two patches sharing the edge get bit-identical points.
std::vector<Vec3> edge_samples(const CanonicalEdge& edge, int segments) {
    std::vector<Vec3> out(static_cast<std::size_t>(segments) + 1);
    for (int k = 0; k <= segments; ++k) {
        const Vec3 p = edge.collapsed ? edge.points[0]
                                      : bezier::de_casteljau(edge.points, static_cast<double>(k) / segments);
        out[static_cast<std::size_t>(edge.reversed ? segments - k : k)] = p;
    }
    return out;
}

struct UnionFind {
    std::vector<std::size_t> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t{0}); }
    std::size_t find(std::size_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

//! Direction classes: 2p = "along u of patch p", 2p + 1 = "along v of patch p". Two patches sharing an edge must
//! use the same segment count along it, so the classes of the edge's direction in both patches are merged.
std::size_t direction_class(std::size_t patch, int side) { return 2 * patch + (runs_along_u(side) ? 0 : 1); }

// ---- per-patch grid -------------------------------------------------------------------------------------------

//! Evaluates position and derivatives with the rows' hodographs computed once per patch (the tessellator's inner
//! loop; evaluate_derivatives() is the same arithmetic).
class PatchEvaluator {
public:
    explicit PatchEvaluator(const BezierPatch& patch) : patch_(patch) {
        for (int j = 0; j <= patch.degree_v; ++j) {
            d1_.push_back(bezier::hodograph(row(patch, j), 1));
            d2_.push_back(bezier::hodograph(row(patch, j), 2));
        }
    }

    PatchDerivatives operator()(double u, double v) const {
        const auto count = static_cast<std::size_t>(patch_.degree_v + 1);
        Vec3 c0[kMaxPatchDegree + 1], c1[kMaxPatchDegree + 1], c2[kMaxPatchDegree + 1];
        for (std::size_t j = 0; j < count; ++j) {
            c0[j] = bezier::de_casteljau(row(patch_, static_cast<int>(j)), u);
            c1[j] = d1_[j].empty() ? Vec3{} : bezier::de_casteljau(d1_[j], u);
            c2[j] = d2_[j].empty() ? Vec3{} : bezier::de_casteljau(d2_[j], u);
        }
        const std::span<const Vec3> s0(c0, count), s1(c1, count), s2(c2, count);
        PatchDerivatives d;
        d.position = bezier::de_casteljau(s0, v);
        d.dv = bezier::derivative(s0, v, 1);
        d.dvv = bezier::derivative(s0, v, 2);
        d.du = bezier::de_casteljau(s1, v);
        d.duv = bezier::derivative(s1, v, 1);
        d.duu = bezier::de_casteljau(s2, v);
        return d;
    }

private:
    const BezierPatch& patch_;
    std::vector<std::vector<Vec3>> d1_, d2_;
};

struct Grid {
    std::vector<Vec3> positions;  //!< (nu + 1) x (nv + 1), u fastest
    std::vector<Vec3> normals;
};

Grid patch_grid(const BezierPatch& patch, int nu, int nv) {
    Grid grid;
    const auto stride = static_cast<std::size_t>(nu + 1);
    grid.positions.resize(stride * static_cast<std::size_t>(nv + 1));
    grid.normals.resize(grid.positions.size());
    const PatchEvaluator evaluator(patch);
    const double scale = net_scale(patch);
    const double vanishing = kVanishing * scale * scale;
    for (int j = 0; j <= nv; ++j) {
        const double v = static_cast<double>(j) / nv;
        for (int i = 0; i <= nu; ++i) {
            const double u = static_cast<double>(i) / nu;
            const std::size_t at = static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i);
            const PatchDerivatives d = evaluator(u, v);
            grid.positions[at] = d.position;
            // the common case directly; collapsed edges and parallel tangents take unit_normal's limit
            const Vec3 n = cross(d.du, d.dv);
            grid.normals[at] = norm(n) > vanishing ? normalized(n) : unit_normal(patch, u, v);
        }
    }
    // boundary positions from the canonical edges (overwrites the tensor evaluation there)
    for (int side = 0; side < 4; ++side) {
        const CanonicalEdge edge = canonical_edge(patch, side);
        const int segments = runs_along_u(side) ? nu : nv;
        const std::vector<Vec3> samples = edge_samples(edge, segments);
        for (int k = 0; k <= segments; ++k) {
            const int i = runs_along_u(side) ? k : (side == kEdgeU0 ? 0 : nu);
            const int j = runs_along_u(side) ? (side == kEdgeV0 ? 0 : nv) : k;
            grid.positions[static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i)] =
                samples[static_cast<std::size_t>(k)];
        }
    }
    return grid;
}

}  // namespace

Status validate(std::span<const BezierPatch> patches) {
    for (std::size_t p = 0; p < patches.size(); ++p) {
        const BezierPatch& patch = patches[p];
        const std::string name = "patch " + std::to_string(p);
        for (int degree : {patch.degree_u, patch.degree_v})
            if (degree < 1 || degree > kMaxPatchDegree) {
                GeoError error = make_error(ErrorCode::InvalidArgument,
                                            name + ": degree " + std::to_string(degree) + " is outside 1.." +
                                                std::to_string(kMaxPatchDegree));
                error.element = static_cast<std::int64_t>(p);
                return error;
            }
        const auto expected = static_cast<std::size_t>((patch.degree_u + 1) * (patch.degree_v + 1));
        if (patch.points.size() != expected) {
            GeoError error = make_error(ErrorCode::InvalidArgument,
                                        name + ": degree " + std::to_string(patch.degree_u) + "x" +
                                            std::to_string(patch.degree_v) + " needs " + std::to_string(expected) +
                                            " control points, got " + std::to_string(patch.points.size()));
            error.element = static_cast<std::int64_t>(p);
            return error;
        }
        for (std::size_t k = 0; k < patch.points.size(); ++k)
            if (!is_finite(patch.points[k])) {
                GeoError error = make_error(ErrorCode::NonFinite,
                                            name + ": control point " + std::to_string(k) + " is not finite");
                error.element = static_cast<std::int64_t>(p);
                return error;
            }
    }
    return Ok{};
}

Vec3 evaluate(const BezierPatch& patch, double u, double v) {
    Vec3 column[kMaxPatchDegree + 1];
    for (int j = 0; j <= patch.degree_v; ++j) column[j] = bezier::de_casteljau(row(patch, j), u);
    return bezier::de_casteljau(std::span<const Vec3>(column, static_cast<std::size_t>(patch.degree_v + 1)), v);
}

PatchDerivatives evaluate_derivatives(const BezierPatch& patch, double u, double v) {
    return PatchEvaluator(patch)(u, v);
}

Vec3 unit_normal(const BezierPatch& patch, double u, double v) {
    const double scale = net_scale(patch);
    if (scale == 0) return {};
    const double vanishing = kVanishing * scale * scale;
    const PatchDerivatives d = evaluate_derivatives(patch, u, v);
    const Vec3 n0 = cross(d.du, d.dv);
    if (norm(n0) > vanishing) return normalized(n0);

    // First-order expansion of du x dv along the direction (su, sv) pointing into the patch:
    // n(u + e su, v + e sv) = e [su (duu x dv + du x duv) + sv (duv x dv + du x dvv)] + O(e^2).
    // On a collapsed edge v = 0 (du = duu = 0) this is duv x dv, the normal of the fan around the apex.
    const double su = u < 0.5 ? 1.0 : -1.0, sv = v < 0.5 ? 1.0 : -1.0;
    const Vec3 n1 = su * (cross(d.duu, d.dv) + cross(d.du, d.duv)) + sv * (cross(d.duv, d.dv) + cross(d.du, d.dvv));
    if (norm(n1) > vanishing) return normalized(n1);

    // Higher-order degeneracy (rare): the normal a short way inside, moving closer while it stays defined.
    for (double step : {1e-3, 1e-5, 1e-7}) {
        const PatchDerivatives inside =
            evaluate_derivatives(patch, std::clamp(u + su * step, 0.0, 1.0), std::clamp(v + sv * step, 0.0, 1.0));
        const Vec3 n = cross(inside.du, inside.dv);
        if (norm(n) > vanishing * step * step) return normalized(n);
    }
    return {};
}

double tessellation_error_bound(const BezierPatch& patch, int nu, int nv) {
    const NetBounds m = second_derivative_bounds(patch);
    const double h = 1.0 / nu, k = 1.0 / nv;
    return (m.uu * h * h + 2.0 * m.uv * h * k + m.vv * k * k) / 8.0;
}

Result<TessellationPlan> plan_tessellation(std::span<const BezierPatch> patches, const TessellationOptions& options) {
    if (options.max_segments < 1)
        return make_error(ErrorCode::InvalidArgument, "max_segments must be >= 1");
    if (auto valid = validate(patches); !valid) return valid.error();
    TessellationPlan plan;
    plan.segments.resize(patches.size());

    // 1. what each patch needs on its own
    if (options.tolerance) {
        const double tolerance = *options.tolerance;
        if (!std::isfinite(tolerance) || tolerance <= 0)
            return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number > 0");
        for (std::size_t p = 0; p < patches.size(); ++p) {
            // (1/8)(A/nu^2 + 2B/(nu nv) + C/nv^2) <= (1/8)((A+B)/nu^2 + (B+C)/nv^2) (AM-GM on the middle term);
            // each half is <= tolerance/2 when nu >= sqrt((A+B)/(4 tol)) and nv >= sqrt((B+C)/(4 tol)).
            const NetBounds m = second_derivative_bounds(patches[p]);
            const double need_u = std::ceil(std::sqrt((m.uu + m.uv) / (4.0 * tolerance)));
            const double need_v = std::ceil(std::sqrt((m.uv + m.vv) / (4.0 * tolerance)));
            if (!(need_u <= options.max_segments) || !(need_v <= options.max_segments)) {
                GeoError error = make_error(
                    ErrorCode::BudgetExceeded,
                    "patch " + std::to_string(p) + ": tolerance " + std::to_string(tolerance) + " needs " +
                        std::to_string(static_cast<long long>(std::min(std::max(need_u, need_v), 1e15))) +
                        " segments along one direction; the limit is " + std::to_string(options.max_segments));
                error.element = static_cast<std::int64_t>(p);
                return error;
            }
            plan.segments[p] = {std::max(1, static_cast<int>(need_u)), std::max(1, static_cast<int>(need_v))};
        }
    } else {
        if (options.segments < 1 || options.segments > options.max_segments)
            return make_error(options.segments < 1 ? ErrorCode::InvalidArgument : ErrorCode::BudgetExceeded,
                              "segments must be between 1 and " + std::to_string(options.max_segments) + ", got " +
                                  std::to_string(options.segments));
        for (auto& s : plan.segments) s = {options.segments, options.segments};
    }

    // 2. equal counts along shared edges: merge direction classes of patches that share an edge
    UnionFind classes(2 * patches.size());
    std::map<std::vector<PointKey>, std::size_t> first_owner;  // canonical edge -> direction class
    for (std::size_t p = 0; p < patches.size(); ++p)
        for (int side = 0; side < 4; ++side) {
            CanonicalEdge edge = canonical_edge(patches[p], side);
            if (edge.collapsed) continue;
            const std::size_t cls = direction_class(p, side);
            auto [it, inserted] = first_owner.emplace(std::move(edge.key), cls);
            if (!inserted) classes.unite(cls, it->second);
        }
    std::vector<int> class_segments(2 * patches.size(), 0);
    for (std::size_t p = 0; p < patches.size(); ++p) {
        int& su = class_segments[classes.find(2 * p)];
        int& sv = class_segments[classes.find(2 * p + 1)];
        su = std::max(su, plan.segments[p].nu);
        sv = std::max(sv, plan.segments[p].nv);
    }
    for (std::size_t p = 0; p < patches.size(); ++p) {
        PatchSegments& s = plan.segments[p];
        s = {class_segments[classes.find(2 * p)], class_segments[classes.find(2 * p + 1)]};
        plan.triangles += 2ull * static_cast<std::uint64_t>(s.nu) * static_cast<std::uint64_t>(s.nv);
        plan.vertices += static_cast<std::uint64_t>(s.nu + 1) * static_cast<std::uint64_t>(s.nv + 1);
        plan.error_bound = std::max(plan.error_bound, tessellation_error_bound(patches[p], s.nu, s.nv));
    }
    return plan;
}

Result<PatchTessellation> tessellate_patches(std::span<const BezierPatch> patches, const TessellationOptions& options) {
    auto planned = plan_tessellation(patches, options);
    if (!planned) return planned.error();
    PatchTessellation out;
    out.plan = std::move(planned.value());
    PolygonMesh& mesh = out.mesh;
    mesh.positions.reserve(out.plan.vertices);
    mesh.normals.reserve(out.plan.vertices);
    mesh.uvs.reserve(out.plan.vertices);
    mesh.face_offsets.reserve(out.plan.triangles + 1);
    mesh.face_indices.reserve(3 * out.plan.triangles);
    mesh.uv_indices.reserve(3 * out.plan.triangles);

    std::unordered_map<PointKey, Index, PointKeyHash> welded;
    std::vector<Vec3> normal_sums;
    std::vector<Index> vertex_of, uv_of;  // per grid vertex of the current patch
    for (std::size_t p = 0; p < patches.size(); ++p) {
        if (options.cancel.requested())
            return make_error(ErrorCode::Cancelled, "tessellation cancelled at patch " + std::to_string(p) + " of " +
                                                        std::to_string(patches.size()) + " (deadline or shutdown)");
        const auto [nu, nv] = out.plan.segments[p];
        const Grid grid = patch_grid(patches[p], nu, nv);
        const auto stride = static_cast<std::size_t>(nu + 1);

        // vertices (welded by exact position) and this patch's own uvs
        vertex_of.resize(grid.positions.size());
        uv_of.resize(grid.positions.size());
        for (std::size_t k = 0; k < grid.positions.size(); ++k) {
            const auto next = static_cast<Index>(mesh.positions.size());
            Index index = next;
            if (options.weld) index = welded.emplace(point_key(grid.positions[k]), next).first->second;
            if (index == next) {
                mesh.positions.push_back(grid.positions[k]);
                normal_sums.push_back(grid.normals[k]);
            } else {
                normal_sums[index] += grid.normals[k];
            }
            vertex_of[k] = index;
            uv_of[k] = static_cast<Index>(mesh.uvs.size());
            mesh.uvs.push_back({static_cast<double>(k % stride) / nu, static_cast<double>(k / stride) / nv});
        }

        // two triangles per grid cell, counter-clockwise in (u, v) so that they face du x dv
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const std::size_t a = static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i);
                const std::size_t corners[2][3] = {{a, a + 1, a + 1 + stride}, {a, a + 1 + stride, a + stride}};
                for (const auto& tri : corners) {
                    const Index v0 = vertex_of[tri[0]], v1 = vertex_of[tri[1]], v2 = vertex_of[tri[2]];
                    if (v0 == v1 || v1 == v2 || v0 == v2) continue;  // next to a collapsed edge
                    mesh.add_face({v0, v1, v2});
                    out.face_patches.push_back(static_cast<Index>(p));
                    for (std::size_t c : tri) mesh.uv_indices.push_back(uv_of[c]);
                }
            }
    }

    // Welded vertices average the patches' normals (equal on G1 joins; on a collapsed edge, the fan's limits).
    mesh.normals.resize(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3 n = normalized(normal_sums[v]);
        mesh.normals[v] = norm(n) > 0 ? n : Vec3{0, 0, 1};
    }
    return out;
}

}  // namespace surfaced
