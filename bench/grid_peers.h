// OpenVDB's mesh to level set conversion as the benchmark peer of geometry/implicit/distance_grid.h, behind a plain
// C++ interface so that OpenVDB's (and TBB's) headers compile in grid_openvdb_peer.cpp only. Bench only: never
// linked into the service.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace surfaced::bench {

//! openvdb::tools::meshToLevelSet<FloatGrid> on one thread (tbb::global_control) with a linear transform of voxel
//! size h: voxel (i, j, k) sits at (i h, j h, k h).
class OpenVdbLevelSet {
public:
    //! Converts the mesh (positions: x, y, z per vertex, as float; three indices per triangle) with a narrow band of
    //! half width `band` voxels.
    OpenVdbLevelSet(const std::vector<float>& positions, const std::vector<unsigned>& triangles, double voxel_size,
                    double band);
    ~OpenVdbLevelSet();
    //! The grid's value at voxel (i, j, k) (the background +-band * h outside its narrow band).
    float value(int i, int j, int k) const;
    std::size_t active_voxels() const;
    std::size_t memory_bytes() const;  //!< the grid's own count (memUsage)

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};
std::string openvdb_version();

}  // namespace surfaced::bench
