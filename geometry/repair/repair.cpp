// repair_mesh: the steps of repair.h run in order over a working copy of the faces, then the output assembled from
// the fans (one vertex each), the kept faces (reversed where needed) and the remapped attributes and tags.
#include "geometry/repair/repair.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/repair/components.h"
#include "geometry/repair/fans.h"
#include "geometry/repair/fill_holes.h"
#include "geometry/repair/glue.h"
#include "geometry/repair/mesh_edges.h"
#include "geometry/repair/weld.h"
#include "geometry/repair/work_faces.h"

namespace surfaced {

using namespace repair_detail;

namespace {

GeoError cancelled() { return make_error(ErrorCode::Cancelled, "mesh repair cancelled"); }

//! Output vertex of every kept corner: one per fan; the first fan of a vertex (in corner order) keeps the vertex,
//! renumbered in the input's order, further fans get copies numbered after all kept vertices.
struct VertexAssignment {
    std::vector<Index> of_corner;  //!< output vertex of each working corner (kInvalidIndex: face dropped)
    std::vector<Index> source;     //!< input vertex of each output vertex
    std::vector<Index> of_input;   //!< output vertex of each input vertex (its first fan), or kInvalidIndex
};

//! `fan` empty: every vertex has one fan (no copies).
VertexAssignment assign_vertices(const CornerTable& table, const std::vector<Index>& fan,
                                 const std::vector<std::uint8_t>& keep_face, const std::vector<Index>& weld,
                                 RepairReport& report) {
    const std::size_t n_in = weld.size();
    constexpr Index kCopy = Index{1} << 31;  // marks a copy's number in fan_vertex until numbering is known
    std::vector<Index> fan_vertex(fan.empty() ? 0 : table.corner_count(), kInvalidIndex);
    std::vector<std::uint8_t> used(n_in, 0);
    std::vector<Index> copy_source;
    for (std::size_t f = 0; f + 1 < table.offsets.size(); ++f) {
        if (!keep_face[f]) continue;
        for (Index c = table.offsets[f]; c < table.offsets[f + 1]; ++c) {
            const Index v = table.indices[c];
            if (fan.empty()) {
                used[v] = 1;
                continue;
            }
            Index& out = fan_vertex[fan[c]];
            if (out != kInvalidIndex) continue;
            if (!used[v]) {
                used[v] = 1;
                out = v;
            } else {
                out = kCopy | static_cast<Index>(copy_source.size());
                copy_source.push_back(v);
            }
        }
    }
    VertexAssignment result;
    result.of_input.assign(n_in, kInvalidIndex);
    for (Index v = 0; v < n_in; ++v) {
        if (used[v]) {
            result.of_input[v] = static_cast<Index>(result.source.size());
            result.source.push_back(v);
        } else if (weld[v] == v) {
            ++report.unreferenced;
        }
    }
    const auto kept = static_cast<Index>(result.source.size());
    result.source.insert(result.source.end(), copy_source.begin(), copy_source.end());
    report.nonmanifold_split = copy_source.size();
    for (Index v = 0; v < n_in; ++v) result.of_input[v] = result.of_input[weld[v]];
    result.of_corner.assign(table.corner_count(), kInvalidIndex);
    for (std::size_t f = 0; f + 1 < table.offsets.size(); ++f) {
        if (!keep_face[f]) continue;
        for (Index c = table.offsets[f]; c < table.offsets[f + 1]; ++c) {
            if (fan.empty()) {
                result.of_corner[c] = result.of_input[table.indices[c]];
                continue;
            }
            const Index out = fan_vertex[fan[c]];
            result.of_corner[c] = (out & kCopy) ? kept + (out & ~kCopy) : result.of_input[out];
        }
    }
    return result;
}

//! Creases and corners follow their vertices, hole tags their faces; anything whose element is gone is dropped.
SubdivisionTags remap_tags(const SubdivisionTags& tags, const std::vector<Index>& vertex_of_input,
                           const std::vector<Index>& face_of_input) {
    SubdivisionTags out;
    out.boundary = tags.boundary;
    for (const Crease& c : tags.creases) {
        const Index a = vertex_of_input[c.v0], b = vertex_of_input[c.v1];
        if (a != kInvalidIndex && b != kInvalidIndex && a != b) out.creases.push_back({a, b, c.sharpness});
    }
    for (const Corner& c : tags.corners)
        if (vertex_of_input[c.vertex] != kInvalidIndex) out.corners.push_back({vertex_of_input[c.vertex], c.sharpness});
    for (Index h : tags.holes)
        if (face_of_input[h] != kInvalidIndex) out.holes.push_back(face_of_input[h]);
    return out;
}

//! Reverses a face in place, keeping its first corner: a b c d -> a d c b.
template <class T>
void reverse_face(T* first, std::size_t n) {
    std::reverse(first + 1, first + n);
}

class Repairer {
public:
    Repairer(const PolygonMesh& mesh, const RepairOptions& options) : in_(mesh), options_(options) {}
    Result<RepairResult> run();

private:
    //! Builds the output mesh from the kept working faces; `reversed` gets one entry per output face.
    PolygonMesh assemble(const WorkFaces& work, const VertexAssignment& vertices,
                         const std::vector<std::uint8_t>& keep_face, const std::vector<std::uint8_t>& flip);
    //! After holes were closed: reverses the closed components that now have a negative volume.
    void orient_filled(PolygonMesh& mesh);

    const PolygonMesh& in_;
    const RepairOptions& options_;
    RepairReport report_;
    std::vector<std::uint8_t> reversed_;  // per output face
};

Result<RepairResult> Repairer::run() {
    const std::vector<Index> weld = weld_targets(in_.positions, options_.weld_tolerance);
    for (Index v = 0; v < weld.size(); ++v) report_.welded += weld[v] != v;
    if (options_.cancel.requested()) return cancelled();

    const WorkFaces work = clean_faces(in_, weld);
    report_.degenerate = work.degenerate;
    report_.duplicate = work.duplicate;
    if (options_.cancel.requested()) return cancelled();

    const CornerTable& table = work.table;
    const EdgeGroups& edges = work.edges;
    Gluing glue = glue_faces(table, edges, options_.orient);
    if (options_.cancel.requested()) return cancelled();
    const std::vector<Index> fan = fan_of_corners(table, edges, glue.partner, in_.vertex_count());
    const Components components = find_components(table, glue.partner);
    if (options_.orient) orient_outward(table, in_.positions, glue.partner, components, glue.flip);
    if (options_.cancel.requested()) return cancelled();

    const std::size_t faces = work.source.size();
    std::vector<std::uint8_t> keep_face(faces, 1);
    std::vector<std::uint8_t> dropped_component(faces, 0);
    for (Index f = 0; f < faces; ++f) {
        const Index root = components.of_face[f];
        if (components.face_count[root] >= options_.min_component_faces) continue;
        keep_face[f] = 0;
        ++report_.removed_faces;
        if (!dropped_component[root]) ++report_.small_components;
        dropped_component[root] = 1;
    }
    report_.components = components.count - report_.small_components;

    const VertexAssignment vertices = assign_vertices(table, fan, keep_face, weld, report_);
    if (options_.max_hole_edges == 0 && !report_.changed()) {  // nothing to assemble unless a face is reversed
        bool flipped = false;
        for (Index f = 0; f < faces && !flipped; ++f) flipped = keep_face[f] && glue.flip[f];
        if (!flipped) return RepairResult{in_, report_};
    }
    PolygonMesh out = assemble(work, vertices, keep_face, glue.flip);
    if (options_.max_hole_edges > 0) {
        if (options_.cancel.requested()) return cancelled();
        const HoleFill filled = fill_holes(out, options_.max_hole_edges, vertices.source);
        report_.holes_filled = filled.holes;
        report_.fill_faces = filled.faces;
        reversed_.resize(out.face_count(), 0);
        if (filled.holes > 0 && options_.orient) orient_filled(out);
    }
    for (std::size_t f = 0; f + report_.fill_faces < out.face_count(); ++f) report_.flipped += reversed_[f];
    if (report_.flipped > 0) out.normals.clear();
    if (!report_.changed()) return RepairResult{in_, report_};
    return RepairResult{std::move(out), report_};
}

PolygonMesh Repairer::assemble(const WorkFaces& work, const VertexAssignment& vertices,
                               const std::vector<std::uint8_t>& keep_face, const std::vector<std::uint8_t>& flip) {
    PolygonMesh out;
    out.positions.reserve(vertices.source.size());
    for (Index v : vertices.source) out.positions.push_back(in_.positions[v]);
    if (in_.has_normals())
        for (Index v : vertices.source) out.normals.push_back(in_.normals[v]);
    const bool uvs = in_.has_uvs();
    if (uvs) out.uvs = in_.uvs;
    out.face_offsets.reserve(keep_face.size() + 1);
    out.face_indices.reserve(work.indices.size());
    if (uvs) out.uv_indices.reserve(work.indices.size());
    reversed_.reserve(keep_face.size());
    std::vector<Index> face_of_input(in_.face_count(), kInvalidIndex);
    for (Index f = 0; f < keep_face.size(); ++f) {
        if (!keep_face[f]) continue;
        face_of_input[work.source[f]] = static_cast<Index>(out.face_count());
        const Index begin = work.offsets[f], n = work.offsets[f + 1] - begin;
        const std::size_t at = out.face_indices.size();
        for (Index c = begin; c < begin + n; ++c) out.face_indices.push_back(vertices.of_corner[c]);
        out.face_offsets.push_back(static_cast<Index>(out.face_indices.size()));
        if (uvs) {
            const Index in_begin = in_.face_offsets[work.source[f]];
            out.uv_indices.insert(out.uv_indices.end(), in_.uv_indices.begin() + in_begin,
                                  in_.uv_indices.begin() + in_begin + n);
        }
        reversed_.push_back(flip[f]);
        if (!flip[f]) continue;
        reverse_face(out.face_indices.data() + at, n);
        if (uvs) reverse_face(out.uv_indices.data() + at, n);
    }
    out.tags = remap_tags(in_.tags, vertices.of_input, face_of_input);
    return out;
}

void Repairer::orient_filled(PolygonMesh& mesh) {
    const CornerTable table = make_corner_table(mesh.face_offsets, mesh.face_indices);
    const EdgeGroups edges = group_edges(table, mesh.vertex_count());
    std::vector<Index> partner(table.corner_count(), kInvalidIndex);
    for (std::size_t e = 0; e < edges.edge_count(); ++e) {
        if (edges.size(e) != 2) continue;
        partner[edges.of(e)[0]] = edges.of(e)[1];
        partner[edges.of(e)[1]] = edges.of(e)[0];
    }
    std::vector<std::uint8_t> flip(mesh.face_count(), 0);
    orient_outward(table, mesh.positions, partner, find_components(table, partner), flip);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        if (!flip[f]) continue;
        reversed_[f] ^= 1;
        const Index at = mesh.face_offsets[f];
        reverse_face(mesh.face_indices.data() + at, mesh.face_size(f));
        if (mesh.has_uvs()) reverse_face(mesh.uv_indices.data() + at, mesh.face_size(f));
    }
}

}  // namespace

Result<RepairResult> repair_mesh(const PolygonMesh& mesh, const RepairOptions& options) {
    if (!(options.weld_tolerance >= 0) || !std::isfinite(options.weld_tolerance))
        return make_error(ErrorCode::InvalidArgument, "weld_tolerance must be finite and >= 0");
    ValidateOptions validate_options;
    validate_options.allow_repeated_vertices = true;
    if (Status valid = validate(mesh, validate_options); !valid) return valid.error();
    if (options.cancel.requested()) return cancelled();
    return Repairer(mesh, options).run();
}

}  // namespace surfaced
