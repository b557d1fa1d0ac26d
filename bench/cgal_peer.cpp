// The only translation unit that includes CGAL (see cgal_peer.h).
#include "bench/cgal_peer.h"

#include <chrono>
#include <cstdint>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/version.h>

namespace surfaced::bench {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Clock = std::chrono::steady_clock;
namespace SMS = CGAL::Surface_mesh_simplification;

//! Stops when the live face count reaches the target (CGAL 5.5's Count_stop_predicate counts edges, which only maps
//! onto faces exactly for closed meshes).
class FaceCountStop {
public:
    FaceCountStop(const Mesh& mesh, std::size_t target) : mesh_(&mesh), target_(target) {}

    template <typename Cost, typename Profile>
    bool operator()(const Cost& /*current_cost*/, const Profile& /*profile*/, std::size_t /*initial_edges*/,
                    std::size_t /*current_edges*/) const {
        return mesh_->number_of_faces() <= target_;
    }

private:
    const Mesh* mesh_;
    std::size_t target_;
};

}  // namespace

CgalSimplifyResult cgal_simplify(const std::vector<double>& positions, const std::vector<unsigned>& triangles,
                                 std::size_t target_faces) {
    CgalSimplifyResult result;
    const std::size_t vertex_count = positions.size() / 3;
    const auto start = Clock::now();

    Mesh mesh;
    mesh.reserve(static_cast<Mesh::size_type>(vertex_count), static_cast<Mesh::size_type>(3 * triangles.size() / 2),
                 static_cast<Mesh::size_type>(triangles.size() / 3));
    for (std::size_t v = 0; v < vertex_count; ++v)
        mesh.add_vertex(Kernel::Point_3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]));
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        if (triangles[t] >= vertex_count || triangles[t + 1] >= vertex_count || triangles[t + 2] >= vertex_count) {
            result.error = "triangle " + std::to_string(t / 3) + " has an index out of range";
            return result;
        }
        const Mesh::Face_index f = mesh.add_face(Mesh::Vertex_index(triangles[t]), Mesh::Vertex_index(triangles[t + 1]),
                                                 Mesh::Vertex_index(triangles[t + 2]));
        result.rejected_faces += f == Mesh::null_face();
    }

    const auto collapse_start = Clock::now();
    SMS::GarlandHeckbert_plane_policies<Mesh, Kernel> policies(mesh);
    SMS::edge_collapse(mesh, FaceCountStop(mesh, target_faces),
                       CGAL::parameters::get_cost(policies.get_cost()).get_placement(policies.get_placement()));
    result.collapse_seconds = std::chrono::duration<double>(Clock::now() - collapse_start).count();

    // extract the live vertices (renumbered) and faces
    std::vector<unsigned> remap(mesh.num_vertices(), 0);
    result.positions.reserve(3 * mesh.number_of_vertices());
    unsigned next = 0;
    for (const Mesh::Vertex_index v : mesh.vertices()) {
        remap[static_cast<std::size_t>(v)] = next++;
        const Kernel::Point_3& p = mesh.point(v);
        result.positions.insert(result.positions.end(), {p.x(), p.y(), p.z()});
    }
    result.triangles.reserve(3 * mesh.number_of_faces());
    for (const Mesh::Face_index f : mesh.faces()) {
        std::size_t corners = 0;
        for (const Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
            result.triangles.push_back(remap[static_cast<std::size_t>(v)]);
            ++corners;
        }
        if (corners != 3) {
            result.error = "CGAL returned a face with " + std::to_string(corners) + " corners";
            return result;
        }
    }
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
}

std::string cgal_version() { return CGAL_VERSION_STR; }

}  // namespace surfaced::bench
