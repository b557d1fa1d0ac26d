// libFuzzer target: repair_mesh on whatever read_obj accepts (faces may repeat a vertex), with the default options
// and with tolerance welding, hole filling and small-component removal. The output must pass validate() and
// audit_mesh() must find no defect in it (non-manifold edges or vertices, inconsistent winding, degenerate or
// duplicate faces, inside-out closed components), and the report's counts must add up to the output's size.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "geometry/io/mesh_io.h"
#include "geometry/repair/repair.h"

namespace {

using namespace surfaced;

void check_repair(const PolygonMesh& mesh, const RepairOptions& options) {
    const Result<RepairResult> result = repair_mesh(mesh, options);
    if (!result.ok()) fuzz::fail("repair_mesh failed on a mesh read_obj accepted", result.error().message);
    const PolygonMesh& out = result->mesh;
    const RepairReport& r = result->report;
    const Status valid = validate(out);
    if (!valid.ok()) fuzz::fail("repair_mesh returned a mesh that validate() rejects", valid.error().message);
    const Result<MeshDefects> defects = audit_mesh(out);
    if (!defects.ok()) fuzz::fail("audit_mesh failed on a repaired mesh", defects.error().message);
    const MeshDefects& d = *defects;
    if (d.breaks_manifold() || d.inverted_components)
        fuzz::fail("repaired mesh has defects", "degenerate " + std::to_string(d.degenerate_faces) + ", duplicate " +
                                                    std::to_string(d.duplicate_faces) + ", non-manifold edges " +
                                                    std::to_string(d.nonmanifold_edges) + ", inconsistent edges " +
                                                    std::to_string(d.inconsistent_edges) + ", non-manifold vertices " +
                                                    std::to_string(d.nonmanifold_vertices) + ", inverted " +
                                                    std::to_string(d.inverted_components));
    if (out.vertex_count() != mesh.vertex_count() - r.welded - r.unreferenced + r.nonmanifold_split)
        fuzz::fail("vertex counts do not add up", std::to_string(out.vertex_count()));
    if (out.face_count() != mesh.face_count() - r.degenerate - r.duplicate - r.removed_faces + r.fill_faces)
        fuzz::fail("face counts do not add up", std::to_string(out.face_count()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    ReadOptions read;
    read.allow_repeated_vertices = true;
    read.max_vertices = 100'000;
    read.max_faces = 100'000;
    const Result<PolygonMesh> mesh = read_obj(bytes, read);
    if (!mesh.ok()) return 0;  // the reader itself is fuzz_obj's
    check_repair(*mesh, RepairOptions{});
    RepairOptions thorough;
    thorough.weld_tolerance = 0.01;
    thorough.max_hole_edges = 8;
    thorough.min_component_faces = 2;
    check_repair(*mesh, thorough);
    return 0;
}
