// CGAL's AABB_tree (closest points) and Embree 3 (rays) as benchmark peers for geometry/spatial, behind plain C++
// interfaces so that each library's headers compile in one translation unit (spatial_cgal_peer.cpp,
// spatial_embree_peer.cpp). Bench only: never linked into the service.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace surfaced::bench {

//! CGAL::AABB_tree over CGAL::Triangle_3 (Simple_cartesian<double>) with accelerate_distance_queries().
class CgalTree {
public:
    //! Builds the tree and its distance-query accelerator (positions: x, y, z per vertex; three indices per triangle).
    CgalTree(const std::vector<double>& positions, const std::vector<unsigned>& triangles);
    ~CgalTree();
    //! Closest surface point of each query (x, y, z each), written to `out` (x, y, z each).
    void closest_points(const std::vector<double>& queries, std::vector<double>& out) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};
std::string cgal_version();

//! An Embree 3 scene of one triangle geometry (float vertices), built by a device limited to one thread.
class EmbreeScene {
public:
    EmbreeScene(const std::vector<double>& positions, const std::vector<unsigned>& triangles);
    ~EmbreeScene();
    //! rtcIntersect1 per ray (origin, direction: 6 values per ray, t in [0, inf)); t of the first hit or -1.
    void first_hits(const std::vector<double>& rays, std::vector<double>& t) const;
    std::string error;  //!< empty when the scene was built

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};
std::string embree_version();

}  // namespace surfaced::bench
