// OpenVDB's meshToLevelSet on one thread (grid_peers.h).
#include <memory>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/global_control.h>

#include "bench/grid_peers.h"

namespace surfaced::bench {

struct OpenVdbLevelSet::Impl {
    openvdb::FloatGrid::Ptr grid;
    std::unique_ptr<openvdb::FloatGrid::ConstAccessor> accessor;  // cached tree nodes for nearby lookups
};

OpenVdbLevelSet::OpenVdbLevelSet(const std::vector<float>& positions, const std::vector<unsigned>& triangles,
                                 double voxel_size, double band)
    : impl_(std::make_unique<Impl>()) {
    static const bool initialized = [] {
        openvdb::initialize();
        return true;
    }();
    (void)initialized;
    const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    std::vector<openvdb::Vec3s> points(positions.size() / 3);
    for (std::size_t i = 0; i < points.size(); ++i)
        points[i] = openvdb::Vec3s(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
    std::vector<openvdb::Vec3I> faces(triangles.size() / 3);
    for (std::size_t i = 0; i < faces.size(); ++i)
        faces[i] = openvdb::Vec3I(triangles[3 * i], triangles[3 * i + 1], triangles[3 * i + 2]);
    const auto transform = openvdb::math::Transform::createLinearTransform(voxel_size);
    impl_->grid =
        openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, faces, static_cast<float>(band));
    impl_->accessor = std::make_unique<openvdb::FloatGrid::ConstAccessor>(impl_->grid->getConstAccessor());
}

OpenVdbLevelSet::~OpenVdbLevelSet() = default;

float OpenVdbLevelSet::value(int i, int j, int k) const { return impl_->accessor->getValue(openvdb::Coord(i, j, k)); }

std::size_t OpenVdbLevelSet::active_voxels() const { return impl_->grid->activeVoxelCount(); }

std::size_t OpenVdbLevelSet::memory_bytes() const { return impl_->grid->memUsage(); }

std::string openvdb_version() { return openvdb::getLibraryVersionString(); }

}  // namespace surfaced::bench
