// PointCloud: positions with optional per-point normals and colours, the point-set counterpart of PolygonMesh.
// Readers and writers are in geometry/io/pointcloud_io.h (PLY, OBJ, XYZ) and geometry/io/pointcloud_glb.h (GLB).
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"

namespace surfaced {

//! Linear RGBA, each channel in [0, 1].
struct Color {
    float r = 0, g = 0, b = 0, a = 1;
};

struct PointCloud {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  //!< size 0 or positions.size(); unit length when present
    std::vector<Color> colors;  //!< size 0 or positions.size()
    bool has_alpha = false;     //!< colors carry a meaningful alpha (written as RGBA rather than RGB)
    //! Optional per-point confidence (PLY `confidence` or `quality`): size 0 or positions.size(), finite, >= 0.
    //! Reconstruction uses it through weight_normals_by_confidence (pointcloud/confidence.h).
    std::vector<float> confidence;

    std::size_t size() const { return positions.size(); }
    bool empty() const { return positions.empty(); }
    bool has_normals() const { return !normals.empty(); }
    bool has_colors() const { return !colors.empty(); }
    bool has_confidence() const { return !confidence.empty(); }
    Box3 bounds() const {
        Box3 box;
        for (const Vec3& p : positions) box.add(p);
        return box;
    }
};

//! Checks what every point-cloud algorithm and writer relies on: attribute arrays sized 0 or size(), finite
//! positions and normals, colour channels in [0, 1], confidences finite and >= 0. The error names the point (GeoError::element, kind Vertex).
Status validate(const PointCloud& cloud);

}  // namespace surfaced
