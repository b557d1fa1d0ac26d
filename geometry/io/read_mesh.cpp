#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"

namespace surfaced {

Result<PolygonMesh> read_mesh(std::string_view bytes, MeshFormat format, const ReadOptions& options,
                              ReadReport* report) {
    if (report) *report = ReadReport{};
    if (format == MeshFormat::Glb || format == MeshFormat::Gltf) {
        GltfReadReport gltf;
        auto mesh = format == MeshFormat::Glb ? read_glb(bytes, options, &gltf) : read_gltf(bytes, options, &gltf);
        if (report) report->skipped_primitives = gltf.skipped_primitives;
        return mesh;
    }
    switch (format) {
        case MeshFormat::Obj: return read_obj(bytes, options, report);
        case MeshFormat::Off: return read_off(bytes, options, report);
        case MeshFormat::Ply: return read_ply(bytes, options, report);
        case MeshFormat::Stl: return read_stl(bytes, options);
        case MeshFormat::Glb: return read_glb(bytes, options);
        case MeshFormat::Gltf: return read_gltf(bytes, options);
    }
    return make_error(ErrorCode::Internal, "unknown mesh format");
}

}  // namespace surfaced
