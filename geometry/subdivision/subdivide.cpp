#include "geometry/subdivision/subdivide.h"

namespace surfaced {

Result<PolygonMesh> subdivide(const PolygonMesh&, const SubdivisionOptions&) {
    return make_error(ErrorCode::Unsupported, "subdivision is being written");
}
std::uint64_t predicted_face_count(const PolygonMesh& mesh, SubdivisionScheme, int) { return mesh.face_count(); }
std::uint64_t predicted_vertex_count(const PolygonMesh& mesh, SubdivisionScheme, int) { return mesh.vertex_count(); }

}  // namespace surfaced
