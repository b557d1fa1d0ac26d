// The expansion (Barill et al. sec. 3.2, to second order). The solid angle of a triangle at q is the integral over
// it of n . F(x - q), F(y) = y / |y|^3. With y = center - q and x = center + delta, Taylor's theorem gives
//   n_i F_i(y + delta) = n_i F_i + n_i dF_i/dy_j delta_j + 1/2 n_i d2F_i/dy_j dy_k delta_j delta_k + R
//   dF_i/dy_j = delta_ij / |y|^3 - 3 y_i y_j / |y|^5
//   d2F_i/dy_j dy_k = -3 (delta_ij y_k + delta_ik y_j + delta_jk y_i) / |y|^5 + 15 y_i y_j y_k / |y|^7
// and the node's value is these derivatives contracted with the integrals of n, n delta^T and n delta delta^T over its
// triangles (WindingNode). Over a triangle delta is linear, so the integral of delta is area * (centroid - center),
// and the integral of delta delta^T is area / 12 * (sum of v v^T + s s^T) over its corners v (relative to the
// centre), s their sum. F = -grad 1/|y|, so R is a sixth of a fourth derivative of 1/|y|; directional derivatives of
// order n of 1/|y| are bounded by n! / |y|^(n+1) (Legendre's expansion, |P_n| <= 1), and for a symmetric form the
// mixed derivative is bounded by the directional one, so |R| <= 4 |delta|^3 / (d - r)^5 pointwise: the bound.
#include "geometry/spatial/winding_number.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/spatial/traversal_stack.h"

namespace surfaced {

namespace {

constexpr double kInv4Pi = 0.25 / std::numbers::pi;

//! The integrals of a node's triangles while the tree is built. With delta = x - center over the node's triangles
//! and n their unit normals:
struct WindingNode {
    Vec3 center;  //!< area-weighted centroid of the node's triangles (box centre when they have no area)
    //! every vertex of the node's triangles is within this distance of `center`
    double radius = 0;
    Vec3 area_normal;  //!< integral of n: sum over triangles of area * n (half the cross product of two edges)
    //! integral of delta n^T, row-major: moment[3 j + i] = integral of delta_j n_i
    double moment[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    //! integral of n_i delta_j delta_k, symmetric in j, k: second[6 i + s] for (j, k) = xx, yy, zz, xy, xz, yz
    double second[18] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    double area = 0;  //!< sum of the triangles' (unsigned) areas
};

//! The node's expansion collapsed: the symmetric part of the moment, the second-order integrals contracted to the
//! linear and cubic forms they contribute (see the top of this file for the terms).
WindingFarField far_field(const WindingNode& n) {
    WindingFarField f;
    f.center = n.center;
    f.radius = n.radius;
    f.area = n.area;
    f.area_normal = n.area_normal;
    const double* m = n.moment;
    f.trace = m[0] + m[4] + m[8];
    // the constants of the terms folded in: 3 y^T M y, 1.5 (2 D + T) . y, 7.5 sum C_ijk y_i y_j y_k
    f.quadratic[0] = 3 * m[0];
    f.quadratic[1] = 3 * m[4];
    f.quadratic[2] = 3 * m[8];
    f.quadratic[3] = 1.5 * (m[1] + m[3]);
    f.quadratic[4] = 1.5 * (m[2] + m[6]);
    f.quadratic[5] = 1.5 * (m[5] + m[7]);
    // C_ijk = second[6 i + s], s for (j, k) = xx, yy, zz, xy, xz, yz
    const double *a = n.second, *b = n.second + 6, *c = n.second + 12;
    // D_k = sum_i C_iik, T_k = sum_j C_kjj
    f.linear = Vec3{2 * (a[0] + b[3] + c[4]) + (a[0] + a[1] + a[2]), 2 * (a[3] + b[1] + c[5]) + (b[0] + b[1] + b[2]),
                    2 * (a[4] + b[5] + c[2]) + (c[0] + c[1] + c[2])} *
               1.5;
    // sum_ijk C_ijk y_i y_j y_k by monomial
    const double cubic[10] = {a[0],
                              b[1],
                              c[2],
                              2 * a[3] + b[0],
                              2 * a[4] + c[0],
                              a[1] + 2 * b[3],
                              2 * b[5] + c[1],
                              a[2] + 2 * c[4],
                              b[2] + 2 * c[5],
                              2 * (a[5] + b[4] + c[3])};
    for (int i = 0; i < 10; ++i) f.cubic[i] = 7.5 * cubic[i];
    return f;
}

//! The far-field value (times 4 pi) of a node at query offset y = center - q, |y|^2 = d2.
double expansion(const WindingFarField& f, const Vec3& y, double d2) {
    const double inv2 = 1.0 / d2, inv3 = std::sqrt(inv2) * inv2;
    const double x = y.x, yy = y.y, z = y.z, x2 = x * x, y2 = yy * yy, z2 = z * z;
    const double* s = f.quadratic;
    const double first = dot(f.area_normal, y) + f.trace;
    const double second =
        s[0] * x2 + s[1] * y2 + s[2] * z2 + 2.0 * (s[3] * x * yy + s[4] * x * z + s[5] * yy * z) + dot(f.linear, y);
    const double* c = f.cubic;
    const double cubic = x * (c[0] * x2 + c[5] * y2 + c[7] * z2 + c[9] * yy * z) +
                         yy * (c[1] * y2 + c[3] * x2 + c[8] * z2) + z * (c[2] * z2 + c[4] * x2 + c[6] * y2);
    return inv3 * (first + inv2 * (cubic * inv2 - second));
}

//! Adds a * (v_j v_k) for the six (j, k) of the symmetric layout, to the three rows i weighted by w_i.
void add_second(double* second, const Vec3& w, const Vec3& u, const Vec3& v) {
    const double jk[6] = {u.x * v.x,
                          u.y * v.y,
                          u.z * v.z,
                          0.5 * (u.x * v.y + u.y * v.x),
                          0.5 * (u.x * v.z + u.z * v.x),
                          0.5 * (u.y * v.z + u.z * v.y)};
    for (int i = 0; i < 3; ++i)
        for (int s = 0; s < 6; ++s) second[6 * i + s] += w[i] * jk[s];
}

double leaf_sum(const TriangleBvh& bvh, const BvhNode& node, const Vec3& q) {
    double sum = 0;
    for (Index i = node.index; i < node.index + node.count; ++i) {
        const BvhTriangle& t = bvh.triangles[i];
        sum += triangle_solid_angle(q, t.p[0], t.p[1], t.p[2]);
    }
    return sum;
}

}  // namespace

double triangle_solid_angle(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 u = a - q, v = b - q, w = c - q;
    const double lu = norm(u), lv = norm(v), lw = norm(w);
    const double numerator = dot(u, cross(v, w));
    const double denominator = lu * lv * lw + dot(u, v) * lw + dot(u, w) * lv + dot(v, w) * lu;
    return 2.0 * std::atan2(numerator, denominator);
}

WindingTree build_winding_tree(const TriangleBvh& bvh) {
    WindingTree tree;
    tree.nodes.resize(bvh.nodes.size());
    // Children follow their parent in the depth-first array, so a reverse sweep sees both before the parent: it is a
    // post-order (right subtree, left subtree, node), and the integrals of the nodes whose parent is still to come
    // are a stack, the left child on top. Only the far-field form of each node is kept.
    std::vector<WindingNode> pending;
    for (std::size_t k = bvh.nodes.size(); k-- > 0;) {
        const BvhNode& node = bvh.nodes[k];
        WindingNode out;
        const Vec3 box_centre = (node.bounds.min + node.bounds.max) * 0.5;
        if (node.is_leaf()) {
            Vec3 weighted;
            for (Index i = node.index; i < node.index + node.count; ++i) {
                const BvhTriangle& t = bvh.triangles[i];
                const Vec3 an = cross(t.p[1] - t.p[0], t.p[2] - t.p[0]) * 0.5;
                const double area = norm(an);
                out.area_normal += an;
                out.area += area;
                weighted += (t.p[0] + t.p[1] + t.p[2]) * (area / 3.0);
            }
            out.center = out.area > 0 ? weighted * (1.0 / out.area) : box_centre;
            for (Index i = node.index; i < node.index + node.count; ++i) {
                const BvhTriangle& t = bvh.triangles[i];
                const Vec3 an = cross(t.p[1] - t.p[0], t.p[2] - t.p[0]) * 0.5;
                const Vec3 delta = (t.p[0] + t.p[1] + t.p[2]) * (1.0 / 3.0) - out.center;
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) out.moment[3 * r + c] += delta[r] * an[c];
                // integral of delta delta^T = area / 12 (sum v v^T + s s^T): n_i times it is an_i / 12 (...)
                Vec3 s;
                for (const Vec3& p : t.p) {
                    const Vec3 v = p - out.center;
                    s += v;
                    add_second(out.second, an * (1.0 / 12.0), v, v);
                    out.radius = std::max(out.radius, norm(v));
                }
                add_second(out.second, an * (1.0 / 12.0), s, s);
            }
            tree.nodes[k] = far_field(out);
            pending.push_back(out);
            continue;
        }
        assert(pending.size() >= 2);
        const WindingNode l = pending.back();
        pending.pop_back();
        const WindingNode r = pending.back();
        pending.pop_back();
        out.area = l.area + r.area;
        out.area_normal = l.area_normal + r.area_normal;
        out.center = out.area > 0 ? (l.center * l.area + r.center * r.area) * (1.0 / out.area) : box_centre;
        // Shift each child's integrals to the new centre: with delta' = delta + s (s = child centre - centre),
        // integral delta' n^T = M + s N^T and integral n_i delta'_j delta'_k = C_ijk + s_j M_ki + s_k M_ji + s_j s_k N_i
        // (M_ki = integral of delta_k n_i).
        double radius = 0;
        for (const WindingNode* child : {&l, &r}) {
            const Vec3 shift = child->center - out.center;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    out.moment[3 * i + j] += child->moment[3 * i + j] + shift[i] * child->area_normal[j];
            for (int e = 0; e < 18; ++e) out.second[e] += child->second[e];
            for (int i = 0; i < 3; ++i) {
                // row i of s M_i^T + M_i s^T, M_i = (M_xi, M_yi, M_zi) the integral of delta n_i
                const Vec3 mi{child->moment[i], child->moment[3 + i], child->moment[6 + i]};
                Vec3 w;
                w[i] = 1.0;
                add_second(out.second, w, shift, mi);
                add_second(out.second, w, mi, shift);
            }
            add_second(out.second, child->area_normal, shift, shift);
            radius = std::max(radius, norm(shift) + child->radius);
        }
        // the farthest corner of the box bounds every vertex too; keep the smaller of the two bounds
        double corner = 0;
        for (int c = 0; c < 8; ++c) {
            const Vec3 p{(c & 1) ? node.bounds.max.x : node.bounds.min.x,
                         (c & 2) ? node.bounds.max.y : node.bounds.min.y,
                         (c & 4) ? node.bounds.max.z : node.bounds.min.z};
            corner = std::max(corner, norm(p - out.center));
        }
        out.radius = std::min(radius, corner);
        tree.nodes[k] = far_field(out);
        pending.push_back(out);
    }
    return tree;
}

namespace {

//! The hierarchical sum, and the error bound when kBound (the value is the same either way).
template <bool kBound>
Result<WindingNumber> evaluate(const TriangleBvh& bvh, const WindingTree& tree, const Vec3& query,
                               const WindingNumberOptions& options) {
    if (!(options.accuracy > 1) || !std::isfinite(options.accuracy))
        return make_error(ErrorCode::InvalidArgument, "winding number accuracy must be a finite number > 1");
    if (!is_finite(query)) return make_error(ErrorCode::InvalidArgument, "winding number query is not finite");
    WindingNumber out;
    if (bvh.empty()) return out;
    if (options.exact) {
        double sum = 0;
        for (const BvhTriangle& t : bvh.triangles) sum += triangle_solid_angle(query, t.p[0], t.p[1], t.p[2]);
        out.value = sum * kInv4Pi;
        return out;
    }
    assert(tree.nodes.size() == bvh.nodes.size());

    const double beta2 = options.accuracy * options.accuracy;
    double sum = 0, bound = 0;
    spatial_detail::TraversalStack<Index> stack;
    stack.push(0);
    while (!stack.empty()) {
        const Index k = stack.pop();
        const WindingFarField& w = tree.nodes[k];
        const Vec3 y = w.center - query;
        const double d2 = dot(y, y);
        if (d2 > beta2 * w.radius * w.radius) {
            sum += expansion(w, y, d2);
            if constexpr (kBound) {
                const double gap = std::sqrt(d2) - w.radius;
                const double r3 = w.radius * w.radius * w.radius;
                bound += 4.0 * w.area * r3 / (gap * gap * gap * gap * gap);
            }
            continue;
        }
        const BvhNode& node = bvh.nodes[k];
        if (node.is_leaf()) {
            sum += leaf_sum(bvh, node, query);
            continue;
        }
        stack.push(k + 1);
        stack.push(node.index);
    }
    out.value = sum * kInv4Pi;
    out.error_bound = bound * kInv4Pi;
    return out;
}

}  // namespace

Result<WindingNumber> winding_number(const TriangleBvh& bvh, const WindingTree& tree, const Vec3& query,
                                     const WindingNumberOptions& options) {
    return evaluate<true>(bvh, tree, query, options);
}

Result<double> winding_number_value(const TriangleBvh& bvh, const WindingTree& tree, const Vec3& query,
                                    const WindingNumberOptions& options) {
    auto w = evaluate<false>(bvh, tree, query, options);
    if (!w) return w.error();
    return w->value;
}

}  // namespace surfaced
