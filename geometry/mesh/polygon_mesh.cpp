#include "geometry/mesh/polygon_mesh.h"

#include <algorithm>
#include <string>

namespace surfaced {

void PolygonMesh::add_face(std::span<const Index> vertices) {
    face_indices.insert(face_indices.end(), vertices.begin(), vertices.end());
    face_offsets.push_back(static_cast<Index>(face_indices.size()));
}

bool PolygonMesh::is_triangle_mesh() const {
    for (std::size_t f = 0; f < face_count(); ++f)
        if (face_size(f) != 3) return false;
    return true;
}

Box3 PolygonMesh::bounds() const {
    Box3 box;
    for (const Vec3& p : positions) box.add(p);
    return box;
}

Status validate(const PolygonMesh& mesh) { return validate(mesh, ValidateOptions{}); }

Status validate(const PolygonMesh& mesh, const ValidateOptions& options) {
    const std::size_t nv = mesh.positions.size();
    if (mesh.face_offsets.empty() || mesh.face_offsets.front() != 0 ||
        mesh.face_offsets.back() != mesh.face_indices.size())
        return make_error(ErrorCode::InvalidArgument, "face offsets do not match the face index array");
    for (std::size_t v = 0; v < nv; ++v)
        if (!is_finite(mesh.positions[v]))
            return element_error(ErrorCode::NonFinite, "vertex " + std::to_string(v) + " has a non-finite coordinate",
                                 ElementKind::Vertex, static_cast<std::int64_t>(v));
    std::vector<Index> scratch;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        if (mesh.face_offsets[f + 1] < mesh.face_offsets[f])
            return make_error(ErrorCode::InvalidArgument,
                              "face offsets are not increasing at face " + std::to_string(f));
        auto face = mesh.face(f);
        const auto fi = static_cast<std::int64_t>(f);
        if (face.size() < 3)
            return element_error(
                ErrorCode::DegenerateFace,
                "face " + std::to_string(f) + " has " + std::to_string(face.size()) + " vertices (at least 3 needed)",
                ElementKind::Face, fi);
        for (Index v : face)
            if (v >= nv)
                return element_error(ErrorCode::IndexOutOfRange,
                                     "face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                                         " but there are " + std::to_string(nv) + " vertices",
                                     ElementKind::Face, fi);
        if (options.allow_repeated_vertices) continue;
        // the smallest vertex used more than once, if any (triangles, nearly every face there is, without sorting)
        Index dup = kInvalidIndex;
        if (face.size() == 3) {
            const Index a = face[0], b = face[1], c = face[2];
            if (a == b || a == c)
                dup = a;
            else if (b == c)
                dup = b;
        } else {
            scratch.assign(face.begin(), face.end());
            std::sort(scratch.begin(), scratch.end());
            auto it = std::adjacent_find(scratch.begin(), scratch.end());
            if (it != scratch.end()) dup = *it;
        }
        if (dup != kInvalidIndex)
            return element_error(
                ErrorCode::DegenerateFace,
                "face " + std::to_string(f) + " uses vertex " + std::to_string(dup) + " more than once",
                ElementKind::Face, fi);
    }
    if (!mesh.uv_indices.empty()) {
        if (mesh.uv_indices.size() != mesh.face_indices.size())
            return make_error(ErrorCode::InvalidArgument, "uv indices do not parallel the face indices");
        for (std::size_t i = 0; i < mesh.uv_indices.size(); ++i)
            if (mesh.uv_indices[i] >= mesh.uvs.size())
                return make_error(ErrorCode::IndexOutOfRange, "uv index " + std::to_string(mesh.uv_indices[i]) +
                                                                  " out of range (" + std::to_string(mesh.uvs.size()) +
                                                                  " uvs)");
        for (const Vec2& uv : mesh.uvs)
            if (!is_finite(uv)) return make_error(ErrorCode::NonFinite, "a texture coordinate is not finite");
    }
    if (!mesh.normals.empty()) {
        if (mesh.normals.size() != nv)
            return make_error(ErrorCode::InvalidArgument, "normals must have one entry per vertex");
        for (const Vec3& n : mesh.normals)
            if (!is_finite(n)) return make_error(ErrorCode::NonFinite, "a normal is not finite");
    }
    const auto& tags = mesh.tags;
    for (std::size_t i = 0; i < tags.creases.size(); ++i) {
        const Crease& c = tags.creases[i];
        if (c.v0 >= nv || c.v1 >= nv)
            return element_error(ErrorCode::IndexOutOfRange,
                                 "crease " + std::to_string(i) + " refers to a missing vertex", ElementKind::Crease,
                                 static_cast<std::int64_t>(i));
        if (!(c.sharpness >= 0) || !std::isfinite(c.sharpness))
            return element_error(ErrorCode::InvalidArgument,
                                 "crease " + std::to_string(i) + " has an invalid sharpness", ElementKind::Crease,
                                 static_cast<std::int64_t>(i));
    }
    for (std::size_t i = 0; i < tags.corners.size(); ++i) {
        const Corner& c = tags.corners[i];
        if (c.vertex >= nv)
            return element_error(ErrorCode::IndexOutOfRange,
                                 "corner " + std::to_string(i) + " refers to a missing vertex", ElementKind::Corner,
                                 static_cast<std::int64_t>(i));
        if (!(c.sharpness >= 0) || !std::isfinite(c.sharpness))
            return element_error(ErrorCode::InvalidArgument,
                                 "corner " + std::to_string(i) + " has an invalid sharpness", ElementKind::Corner,
                                 static_cast<std::int64_t>(i));
    }
    for (std::size_t i = 0; i < tags.holes.size(); ++i)
        if (tags.holes[i] >= mesh.face_count())
            return element_error(ErrorCode::IndexOutOfRange,
                                 "hole " + std::to_string(i) + " refers to face " + std::to_string(tags.holes[i]) +
                                     " but there are " + std::to_string(mesh.face_count()) + " faces",
                                 ElementKind::Hole, static_cast<std::int64_t>(i));
    return Ok{};
}

}  // namespace surfaced
