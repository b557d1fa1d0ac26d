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

//! The far-field value (times 4 pi) of a node at query offset y = center - q.
double expansion(const WindingNode& n, const Vec3& y, double d2) {
    const double d = std::sqrt(d2);
    const double inv3 = 1.0 / (d2 * d), inv5 = inv3 / d2, inv7 = inv5 / d2;
    // zeroth and first order
    const double* m = n.moment;
    const double trace = m[0] + m[4] + m[8];
    const double yMy = y.x * (m[0] * y.x + m[1] * y.y + m[2] * y.z) + y.y * (m[3] * y.x + m[4] * y.y + m[5] * y.z) +
                       y.z * (m[6] * y.x + m[7] * y.y + m[8] * y.z);
    double value = (dot(n.area_normal, y) + trace) * inv3 - 3.0 * yMy * inv5;
    // second order: C_ijk = integral of n_i delta_j delta_k
    const double yv[3] = {y.x, y.y, y.z};
    double diagonal = 0, traces = 0, cubic = 0;
    for (int i = 0; i < 3; ++i) {
        const double* c = n.second + 6 * i;  // xx, yy, zz, xy, xz, yz
        const double row[3][3] = {{c[0], c[3], c[4]}, {c[3], c[1], c[5]}, {c[4], c[5], c[2]}};
        diagonal += row[i][0] * yv[0] + row[i][1] * yv[1] + row[i][2] * yv[2];  // sum_k C_iik y_k
        traces += yv[i] * (c[0] + c[1] + c[2]);                                 // y_i sum_j C_ijj
        cubic += yv[i] * (c[0] * yv[0] * yv[0] + c[1] * yv[1] * yv[1] + c[2] * yv[2] * yv[2] +
                          2.0 * (c[3] * yv[0] * yv[1] + c[4] * yv[0] * yv[2] + c[5] * yv[1] * yv[2]));
    }
    value += 0.5 * (-3.0 * (2.0 * diagonal + traces) * inv5 + 15.0 * cubic * inv7);
    return value;
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
    // children follow their parent in the array, so a reverse sweep sees both before the parent
    for (std::size_t k = bvh.nodes.size(); k-- > 0;) {
        const BvhNode& node = bvh.nodes[k];
        WindingNode& out = tree.nodes[k];
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
            continue;
        }
        const WindingNode& l = tree.nodes[k + 1];
        const WindingNode& r = tree.nodes[node.index];
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
        const BvhNode& node = bvh.nodes[k];
        const WindingNode& w = tree.nodes[k];
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
