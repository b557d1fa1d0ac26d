// measure_quality (declared in remesh.h): the triangle quality report that remesh() gives before and after, kept
// apart from the remesher since it reads only a PolygonMesh and serves any mesh.
#include "geometry/remesh/remesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

namespace surfaced {

MeshQuality measure_quality(const PolygonMesh& mesh) {
    MeshQuality q;
    q.vertices = mesh.vertex_count();
    constexpr double kRatioCap = 1e30;  // Verdict's VERDICT_DBL_MAX
    double min_angle = std::numbers::pi, ratio_sum = 0;
    std::size_t triangles = 0, below = 0;
    std::vector<std::pair<Index, Index>> edges;  // directed, as the faces traverse them
    edges.reserve(mesh.face_indices.size());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        for (std::size_t j = 0; j < t.size(); ++j) edges.push_back({t[j], t[(j + 1) % t.size()]});
        for (std::size_t j = 1; j + 1 < t.size(); ++j) {
            const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[j]], &c = mesh.positions[t[j + 1]];
            const Vec3 corners[3][3] = {{a, b, c}, {b, c, a}, {c, a, b}};
            double smallest = std::numbers::pi;
            for (const auto& k : corners) {
                const Vec3 u = k[1] - k[0], w = k[2] - k[0];
                smallest = std::min(smallest, std::atan2(norm(cross(u, w)), dot(u, w)));
            }
            min_angle = std::min(min_angle, smallest);
            if (smallest < std::numbers::pi / 6) ++below;
            // Verdict radius ratio R / (2 r) = abc s / (8 A^2), s the semi-perimeter
            const double la = norm(b - c), lb = norm(c - a), lc = norm(a - b);
            const double area = 0.5 * norm(cross(b - a, c - a));
            const double s = 0.5 * (la + lb + lc);
            const double denom = 8 * area * area;
            const double ratio = denom > 0 ? std::min(kRatioCap, la * lb * lc * s / denom) : kRatioCap;
            ratio_sum += ratio;
            q.max_radius_ratio = std::max(q.max_radius_ratio, ratio);
            ++triangles;
        }
    }
    q.faces = mesh.face_count();
    if (triangles > 0) {
        q.min_angle_degrees = min_angle * 180.0 / std::numbers::pi;
        q.share_below_30 = static_cast<double>(below) / static_cast<double>(triangles);
        q.mean_radius_ratio = ratio_sum / static_cast<double>(triangles);
    }
    // undirected edges; one used by a single face is a boundary edge
    std::vector<std::pair<Index, Index>> undirected(edges.size());
    for (std::size_t i = 0; i < edges.size(); ++i)
        undirected[i] = {std::min(edges[i].first, edges[i].second), std::max(edges[i].first, edges[i].second)};
    std::sort(undirected.begin(), undirected.end());
    std::vector<Index> valence(mesh.vertex_count(), 0);
    std::vector<std::uint8_t> on_boundary(mesh.vertex_count(), 0);
    double sum = 0, sum2 = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < undirected.size();) {
        std::size_t j = i;
        while (j < undirected.size() && undirected[j] == undirected[i]) ++j;
        const auto [u, w] = undirected[i];
        ++valence[u], ++valence[w];
        if (j - i == 1) on_boundary[u] = on_boundary[w] = 1;
        const double l = norm(mesh.positions[u] - mesh.positions[w]);
        sum += l, sum2 += l * l;
        ++count;
        i = j;
    }
    if (count > 0) {
        q.mean_edge_length = sum / static_cast<double>(count);
        q.edge_length_stddev =
            std::sqrt(std::max(0.0, sum2 / static_cast<double>(count) - q.mean_edge_length * q.mean_edge_length));
    }
    std::size_t used = 0, regular = 0;
    for (std::size_t v = 0; v < valence.size(); ++v) {
        if (valence[v] == 0) continue;
        if (q.valence_histogram.size() <= valence[v]) q.valence_histogram.resize(valence[v] + 1, 0);
        ++q.valence_histogram[valence[v]];
        ++used;
        if (valence[v] == (on_boundary[v] ? 4u : 6u)) ++regular;
    }
    q.share_regular = used ? static_cast<double>(regular) / static_cast<double>(used) : 0.0;
    return q;
}

}  // namespace surfaced
