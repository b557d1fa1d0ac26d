// The only translation unit of bench_poisson_cgal that includes CGAL (see poisson_peer.h).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/poisson_surface_reconstruction.h>

#include <utility>
#include <vector>

#include "bench/poisson_peer.h"

namespace surfaced::bench {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using PointWithNormal = std::pair<Point, Vector>;
using Mesh = CGAL::Surface_mesh<Point>;
}  // namespace

CgalPoissonResult cgal_poisson(const std::vector<double>& points, const std::vector<double>& normals, double sm_radius,
                               double sm_distance) {
    CgalPoissonResult result;
    std::vector<PointWithNormal> input;
    input.reserve(points.size() / 3);
    for (std::size_t i = 0; i + 2 < points.size(); i += 3)
        input.emplace_back(Point(points[i], points[i + 1], points[i + 2]),
                           Vector(normals[i], normals[i + 1], normals[i + 2]));
    result.average_spacing = CGAL::compute_average_spacing<CGAL::Sequential_tag>(
        input, 6, CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PointWithNormal>()));
    Mesh mesh;
    const bool ok = CGAL::poisson_surface_reconstruction_delaunay(
        input.begin(), input.end(), CGAL::First_of_pair_property_map<PointWithNormal>(),
        CGAL::Second_of_pair_property_map<PointWithNormal>(), mesh, result.average_spacing, 20.0, sm_radius,
        sm_distance);
    if (!ok) {
        result.error = "CGAL's reconstruction failed";
        return result;
    }
    std::vector<unsigned> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), 0);
    unsigned next = 0;
    for (const Mesh::Vertex_index v : mesh.vertices()) {
        const Point& p = mesh.point(v);
        result.positions.insert(result.positions.end(), {p.x(), p.y(), p.z()});
        index[v] = next++;
    }
    for (const Mesh::Face_index f : mesh.faces())
        for (const Mesh::Vertex_index v : mesh.vertices_around_face(mesh.halfedge(f)))
            result.triangles.push_back(index[v]);
    return result;
}

}  // namespace surfaced::bench
