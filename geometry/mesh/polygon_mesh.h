// PolygonMesh: the currency type of the library. Flat index arrays, like OpenSubdiv's TopologyDescriptor,
// glTF accessors and Draco: positions, per-face offsets into one index array, optional attributes and
// subdivision tags. Every public algorithm takes and returns this type.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"

namespace surfaced {

//! OpenSubdiv's Sdc::Options::VtxBoundaryInterpolation, by the same names.
enum class BoundaryInterpolation {
    None,           //!< VTX_BOUNDARY_NONE
    EdgeOnly,       //!< VTX_BOUNDARY_EDGE_ONLY: sharp boundary edges, smooth corners (default)
    EdgeAndCorner,  //!< VTX_BOUNDARY_EDGE_AND_CORNER: sharp boundary edges and corners
};

//! Sharpness of the edge between two vertices (order of v0, v1 does not matter).
struct Crease {
    Index v0 = 0, v1 = 0;
    double sharpness = 0;
};

//! Sharpness of a vertex.
struct Corner {
    Index vertex = 0;
    double sharpness = 0;
};

//! Subdivision tags as OpenSubdiv's regression shapes carry them (OBJ `t` lines).
struct SubdivisionTags {
    std::vector<Crease> creases;
    std::vector<Corner> corners;
    std::vector<Index> holes;                       //!< face indices
    std::optional<BoundaryInterpolation> boundary;  //!< from `t interpolateboundary`, if given

    bool empty() const { return creases.empty() && corners.empty() && holes.empty() && !boundary; }
};

struct PolygonMesh {
    std::vector<Vec3> positions;
    //! face f uses face_indices[face_offsets[f] .. face_offsets[f+1]); size = face_count() + 1, first element 0.
    std::vector<Index> face_offsets{0};
    std::vector<Index> face_indices;

    //! Optional face-varying texture coordinates: uv_indices parallels face_indices (empty when there are none).
    std::vector<Vec2> uvs;
    std::vector<Index> uv_indices;

    //! Optional per-vertex normals (size 0 or positions.size()).
    std::vector<Vec3> normals;

    SubdivisionTags tags;

    std::size_t vertex_count() const { return positions.size(); }
    std::size_t face_count() const { return face_offsets.size() - 1; }
    std::size_t face_size(std::size_t f) const { return face_offsets[f + 1] - face_offsets[f]; }
    std::span<const Index> face(std::size_t f) const { return {face_indices.data() + face_offsets[f], face_size(f)}; }
    bool has_uvs() const { return !uv_indices.empty(); }
    bool has_normals() const { return !normals.empty(); }

    //! Append a face given by its vertex indices (no validation: call validate()).
    void add_face(std::span<const Index> vertices);
    void add_face(std::initializer_list<Index> vertices) {
        add_face(std::span<const Index>(vertices.begin(), vertices.size()));
    }

    //! True when every face has exactly three vertices.
    bool is_triangle_mesh() const;
    Box3 bounds() const;
};

//! Checks the invariants every algorithm relies on: offsets well formed, at least 3 vertices per face, indices in
//! range, no vertex repeated within a face, finite coordinates, attribute arrays sized consistently, tag indices in
//! range and sharpness finite and >= 0. The error names the face or vertex (GeoError::element).
struct ValidateOptions {
    //! Faces may use a vertex more than once (`[0, 1, 2, 2]`), as OpenSubdiv allows: subdivision only.
    bool allow_repeated_vertices = false;
};
Status validate(const PolygonMesh& mesh, const ValidateOptions& options);
Status validate(const PolygonMesh& mesh);

}  // namespace surfaced
