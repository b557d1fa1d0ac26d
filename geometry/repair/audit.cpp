// audit_mesh and needs_repair: the defects repair_mesh removes, counted without changing anything.
#include "geometry/repair/repair.h"

#include <cmath>
#include <string>
#include <vector>

#include "geometry/repair/components.h"
#include "geometry/repair/fans.h"
#include "geometry/repair/mesh_edges.h"
#include "geometry/repair/work_faces.h"

namespace surfaced {

using namespace repair_detail;

namespace {

//! Closed components (every half-edge joined) whose signed volume is negative beyond rounding: below -1e-9 times the
//! sum of the faces' absolute volumes (a flat closed component is neither inverted nor not).
std::size_t count_inverted(const CornerTable& table, std::span<const Vec3> positions,
                           const std::vector<Index>& partner) {
    const Components components = find_components(table, partner);
    const std::size_t faces = table.offsets.size() - 1;
    std::vector<std::uint8_t> open(faces, 0);
    for (Index c = 0; c < table.corner_count(); ++c)
        if (partner[c] == kInvalidIndex) open[components.of_face[table.face(c)]] = 1;
    std::vector<double> volume(faces, 0.0), magnitude(faces, 0.0);
    for (Index f = 0; f < faces; ++f) {
        const Index root = components.of_face[f];
        if (open[root]) continue;
        const Vec3& origin = positions[table.indices[table.offsets[root]]];
        volume[root] += face_volume(
            positions, table.indices.subspan(table.offsets[f], table.offsets[f + 1] - table.offsets[f]), origin);
    }
    std::size_t inverted = 0;
    for (Index f = 0; f < faces; ++f)
        if (components.of_face[f] == f && !open[f] && volume[f] < -1e-9 * magnitude[f]) ++inverted;
    return inverted;
}

}  // namespace

namespace {

//! The defects; `whole` false: only enough of them to answer needs_repair (no volumes, one non-manifold vertex at
//! most).
Result<MeshDefects> find_defects(const PolygonMesh& mesh, bool whole) {
    ValidateOptions validate_options;
    validate_options.allow_repeated_vertices = true;
    if (Status valid = validate(mesh, validate_options); !valid) return valid.error();
    const WorkFaces work = clean_faces(mesh, {});
    MeshDefects defects;
    defects.degenerate_faces = work.degenerate;
    defects.duplicate_faces = work.duplicate;
    if (!whole && defects.breaks_manifold()) return defects;
    const CornerTable& table = work.table;
    const EdgeGroups& edges = work.edges;
    // faces on an edge of two are in one fan around its ends whatever their directions
    std::vector<Index> pair(table.corner_count(), kInvalidIndex);
    for (std::size_t e = 0; e < edges.edge_count(); ++e) {
        const auto corners = edges.of(e);
        if (corners.size() > 2) ++defects.nonmanifold_edges;
        if (corners.size() != 2) continue;
        const Index a = corners[0], b = corners[1];
        pair[a] = b;
        pair[b] = a;
        if (table.indices[a] == table.indices[b]) ++defects.inconsistent_edges;
    }
    if (!whole && defects.breaks_manifold()) return defects;
    defects.nonmanifold_vertices = count_split_vertices(table, pair, mesh.vertex_count(), !whole);
    if (!whole) return defects;
    // consistent pairs join the faces into components for the volume test
    if (defects.inconsistent_edges > 0)
        for (Index c = 0; c < table.corner_count(); ++c)
            if (pair[c] != kInvalidIndex && table.indices[pair[c]] == table.indices[c]) pair[c] = kInvalidIndex;
    defects.inverted_components = count_inverted(table, mesh.positions, pair);
    return defects;
}

}  // namespace

Result<MeshDefects> audit_mesh(const PolygonMesh& mesh) { return find_defects(mesh, true); }

Status check_manifold(const PolygonMesh& mesh) {
    const CornerTable table = make_corner_table(mesh.face_offsets, mesh.face_indices);
    const EdgeGroups edges = group_edges(table, mesh.vertex_count());
    // edges: the one whose offending face comes first; corners of an edge are in face order
    constexpr Index kNone = kInvalidIndex;
    Index bad_corner = kNone;
    bool same_direction = false;
    std::vector<Index> pair(table.corner_count(), kNone);
    for (std::size_t e = 0; e < edges.edge_count(); ++e) {
        const auto corners = edges.of(e);
        Index offending = kNone;
        bool same = false;
        if (corners.size() > 2) {
            offending = corners[2];
        } else if (corners.size() == 2) {
            const Index a = corners[0], b = corners[1];
            if (table.indices[a] == table.indices[b]) {
                offending = b;
                same = true;
            } else {
                pair[a] = b;
                pair[b] = a;
            }
        }
        if (offending != kNone && (bad_corner == kNone || table.face(offending) < table.face(bad_corner))) {
            bad_corner = offending;
            same_direction = same;
        }
    }
    if (bad_corner != kNone) {
        const Index f = table.face(bad_corner);
        const std::string edge = "(" + std::to_string(table.indices[bad_corner]) + ", " +
                                 std::to_string(table.indices[table.next(bad_corner)]) + ")";
        return element_error(
            ErrorCode::NonManifold,
            same_direction
                ? "edge " + edge + " is traversed in the same direction by face " + std::to_string(f) +
                      " and another face (inconsistent orientation or a duplicate face)"
                : "edge " + edge + " is shared by more than two faces (face " + std::to_string(f) + " is one)",
            ElementKind::Face, f);
    }
    Index vertex = kNone;
    if (count_split_vertices(table, pair, mesh.vertex_count(), true, &vertex) == 0) return Ok{};
    Index face = kNone;
    for (Index c = 0; c < table.corner_count() && face == kNone; ++c)
        if (table.indices[c] == vertex) face = table.face(c);
    return element_error(ErrorCode::NonManifold,
                         "vertex " + std::to_string(vertex) +
                             " joins several fans of faces (a non-manifold vertex; face " + std::to_string(face) +
                             " uses it)",
                         ElementKind::Face, face);
}

bool needs_repair(const PolygonMesh& mesh) {
    const Result<MeshDefects> defects = find_defects(mesh, false);
    return !defects.ok() || defects->breaks_manifold();
}

}  // namespace surfaced
