#include "geometry/io/gltf_points.h"
#include "geometry/io/pointcloud_io.h"

namespace surfaced {

Result<PointCloud> read_points(std::string_view bytes, PointFormat format, const PointReadOptions& options) {
    switch (format) {
        case PointFormat::Ply: return read_ply_points(bytes, options);
        case PointFormat::Obj: return read_obj_points(bytes, options);
        case PointFormat::Xyz: return read_xyz_points(bytes, options);
        case PointFormat::Glb: return read_glb_points(bytes, options);
        case PointFormat::Gltf: return read_gltf_points(bytes, options);
    }
    return make_error(ErrorCode::Internal, "unknown point format");
}

}  // namespace surfaced
