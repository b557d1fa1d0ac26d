// glTF mesh readers: GLB, and glTF JSON (.gltf) with its buffers embedded as base64 data: URIs, both through the
// same scene path on the checked document of gltf_document.h. The ReadOptions limits are applied to the counts the
// accessors announce before anything is allocated.
// Steps: container (GLB) -> document -> extensionsRequired -> node world transforms -> primitives (plain or Draco;
// points and lines skipped and counted) -> weld by position -> PolygonMesh.
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <unordered_map>

#include "geometry/io/draco_codec.h"
#include "geometry/io/gltf.h"
#include "geometry/io/gltf_document.h"

namespace surfaced {

namespace {

using namespace gltf_doc;

//! The document's accessor reader and the limits of this read.
struct MeshReader : Reader {
    const ReadOptions& options;
};

// ---- assembling the mesh -----------------------------------------------------------------------------------------

//! Exact-position key for welding: glTF duplicates vertices at uv seams and normal creases, our topology must not.
struct PositionKey {
    std::array<std::uint64_t, 3> bits;
    bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
    std::size_t operator()(const PositionKey& k) const {
        std::uint64_t h = 1469598103934665603ull;
        for (std::uint64_t b : k.bits) h = (h ^ b) * 1099511628211ull ^ (b >> 29);
        return static_cast<std::size_t>(h);
    }
};
PositionKey key_of(const Vec3& p) {
    PositionKey key{};
    for (int k = 0; k < 3; ++k) {
        const double v = p[k] == 0.0 ? 0.0 : p[k];  // -0 and +0 are the same place
        std::memcpy(&key.bits[static_cast<std::size_t>(k)], &v, sizeof v);
    }
    return key;
}

struct Builder {
    PolygonMesh mesh;
    std::unordered_map<PositionKey, Index, PositionKeyHash> welded;
    std::vector<Vec2> uvs;  //!< one per corner, deduplicated at the end
    bool all_have_uvs = true;
};

//! Triangle corner lists for the three triangle modes (strips and fans keep a consistent winding).
Result<std::vector<std::uint32_t>> triangles_of(int mode, std::vector<std::uint32_t> idx, const std::string& where,
                                                std::int64_t json_offset) {
    if (mode == kModeTriangles) {
        if (idx.size() % 3 != 0)
            return parse_error(
                "glTF " + where + ": TRIANGLES index count " + std::to_string(idx.size()) + " is not a multiple of 3",
                json_offset);
        return idx;
    }
    std::vector<std::uint32_t> out;
    if (idx.size() < 3) return out;
    out.reserve((idx.size() - 2) * 3);
    for (std::size_t i = 0; i + 2 < idx.size(); ++i) {
        if (mode == kModeTriangleFan)
            out.insert(out.end(), {idx[0], idx[i + 1], idx[i + 2]});
        else if (i % 2 == 0)
            out.insert(out.end(), {idx[i], idx[i + 1], idx[i + 2]});
        else
            out.insert(out.end(), {idx[i + 1], idx[i], idx[i + 2]});
    }
    return out;
}

//! One primitive's vertex data as decoded, before transforming and welding: xyz, uv (empty when absent) and
//! triangle corners.
struct PrimitiveData {
    std::vector<double> positions, texcoords;
    std::vector<std::uint32_t> indices;
};

//! Limits on what the accessors announce, before anything is decoded or allocated.
Status check_announced_counts(const MeshReader& reader, const Builder& b, const Primitive& prim, int position_accessor,
                              const std::string& where) {
    const ReadOptions& limits = reader.options;
    const std::uint64_t announced = reader.doc.accessors[static_cast<std::size_t>(position_accessor)].count;
    if (announced > limits.max_vertices || b.mesh.positions.size() > limits.max_vertices - announced)
        return make_error(ErrorCode::BudgetExceeded, where + ": " + std::to_string(announced) +
                                                         " more vertices exceed the limit of " +
                                                         std::to_string(limits.max_vertices));
    const std::uint64_t announced_corners =
        prim.indices >= 0 ? reader.doc.accessors[static_cast<std::size_t>(prim.indices)].count : announced;
    if (announced_corners / 3 > limits.max_faces || b.mesh.face_count() > limits.max_faces - announced_corners / 3)
        return make_error(ErrorCode::BudgetExceeded, where + ": " + std::to_string(announced_corners / 3) +
                                                         " more triangles exceed the limit of " +
                                                         std::to_string(limits.max_faces));
    return Ok{};
}

//! A KHR_draco_mesh_compression primitive: its buffer view decoded by Draco (within the limits left).
Status decode_draco_primitive(const MeshReader& reader, const Builder& b, const DracoPrimitive& draco, bool has_uv,
                              const std::string& where, PrimitiveData& out) {
    const ReadOptions& limits = reader.options;
    draco_codec::AttributeIds ids;
    const auto pos_id = draco.attributes.find("POSITION");
    if (pos_id == draco.attributes.end())
        return parse_error("glTF " + where + ": " + kDracoExtension + " has no POSITION attribute",
                           reader.doc.json_offset);
    ids.position = pos_id->second;
    if (const auto uv_id = draco.attributes.find("TEXCOORD_0"); has_uv && uv_id != draco.attributes.end())
        ids.texcoord = uv_id->second;
    const auto bytes = reader.doc.views[static_cast<std::size_t>(draco.buffer_view)].bytes;
    const draco_codec::DecodeLimits decode_limits{limits.max_vertices - b.mesh.positions.size(),
                                                  limits.max_faces - b.mesh.face_count()};
    auto decoded = draco_codec::decode({bytes.data(), bytes.size()}, ids, decode_limits);
    if (!decoded) {
        GeoError e = decoded.error();
        e.message = where + ": " + e.message;
        return e;
    }
    out.positions.assign(decoded->positions.begin(), decoded->positions.end());
    out.texcoords.assign(decoded->texcoords.begin(), decoded->texcoords.end());
    out.indices = std::move(decoded->indices);
    return Ok{};
}

//! A plain primitive: POSITION, TEXCOORD_0 and indices read from their accessors, strips and fans made triangles.
Status read_accessor_primitive(const MeshReader& reader, const Primitive& prim, int position_accessor,
                               std::optional<int> uv_accessor, const std::string& where, PrimitiveData& out) {
    auto p = reader.read_floats(position_accessor, 3, "POSITION");
    if (!p) return p.error();
    out.positions = std::move(*p);
    if (uv_accessor) {
        auto t = reader.read_floats(*uv_accessor, 2, "TEXCOORD_0");
        if (!t) return t.error();
        out.texcoords = std::move(*t);
        if (out.texcoords.size() / 2 != out.positions.size() / 3)
            return parse_error("glTF " + where + ": TEXCOORD_0 and POSITION counts differ", reader.doc.json_offset);
    }
    std::vector<std::uint32_t> corners;
    if (prim.indices >= 0) {
        auto i = reader.read_indices(prim.indices);
        if (!i) return i.error();
        corners = std::move(*i);
    } else {
        // No indices: vertices are used in order.
        corners.resize(out.positions.size() / 3);
        for (std::size_t k = 0; k < corners.size(); ++k) corners[k] = static_cast<std::uint32_t>(k);
    }
    auto tris = triangles_of(prim.mode, std::move(corners), where, reader.doc.json_offset);
    if (!tris) return tris.error();
    out.indices = std::move(*tris);
    return Ok{};
}

//! The primitive's vertices transformed by `world` and welded into the mesh being built, its triangles added (with
//! the winding flipped under a mirroring transform) and their corner uvs kept for finish_uvs().
Status append_primitive(Builder& b, const PrimitiveData& data, const Mat4& world, const std::string& where) {
    const std::size_t count = data.positions.size() / 3;
    std::vector<Index> remap(count);
    for (std::size_t v = 0; v < count; ++v) {
        const double x = data.positions[3 * v], y = data.positions[3 * v + 1], z = data.positions[3 * v + 2];
        const Vec3 p{world[0] * x + world[4] * y + world[8] * z + world[12],
                     world[1] * x + world[5] * y + world[9] * z + world[13],
                     world[2] * x + world[6] * y + world[10] * z + world[14]};
        if (!is_finite(p))
            return make_error(ErrorCode::NonFinite, where + ": vertex " + std::to_string(v) + " is not finite", -1, -1,
                              static_cast<std::int64_t>(v));
        auto [it, inserted] = b.welded.try_emplace(key_of(p), static_cast<Index>(b.mesh.positions.size()));
        if (inserted) b.mesh.positions.push_back(p);
        remap[v] = it->second;
    }

    // A mirroring transform turns the triangles inside out; glTF says to flip the winding then.
    const bool flip = determinant3(world) < 0;
    const std::vector<double>& uv = data.texcoords;
    for (std::size_t t = 0; t < data.indices.size() / 3; ++t) {
        std::array<std::uint32_t, 3> c{data.indices[3 * t], data.indices[3 * t + 1], data.indices[3 * t + 2]};
        for (std::uint32_t v : c)
            if (v >= count)
                return make_error(ErrorCode::IndexOutOfRange,
                                  where + ": triangle " + std::to_string(t) + " refers to vertex " + std::to_string(v) +
                                      " of " + std::to_string(count),
                                  -1, -1, static_cast<std::int64_t>(t));
        if (flip) std::swap(c[1], c[2]);
        const Index a = remap[c[0]], bb = remap[c[1]], cc = remap[c[2]];
        if (a == bb || bb == cc || a == cc) continue;  // collapsed by welding: no longer a polygon
        b.mesh.add_face({a, bb, cc});
        for (std::uint32_t v : c) b.uvs.push_back(uv.empty() ? Vec2{} : Vec2{uv[2 * v], 1.0 - uv[2 * v + 1]});
    }
    return Ok{};
}

Status add_primitive(const MeshReader& reader, Builder& b, const Primitive& prim, const Mat4& world,
                     std::size_t mesh_index, std::size_t prim_index) {
    const std::string where =
        "meshes[" + std::to_string(mesh_index) + "].primitives[" + std::to_string(prim_index) + "]";
    const auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end())
        return parse_error("glTF " + where + " has no POSITION", reader.doc.json_offset);
    const auto uv_it = prim.attributes.find("TEXCOORD_0");
    const bool has_uv = uv_it != prim.attributes.end();
    const ReadOptions& limits = reader.options;
    if (auto status = check_announced_counts(reader, b, prim, pos_it->second, where); !status) return status;

    PrimitiveData data;
    Status decoded =
        prim.draco ? decode_draco_primitive(reader, b, *prim.draco, has_uv, where, data)
                   : read_accessor_primitive(reader, prim, pos_it->second,
                                             has_uv ? std::optional<int>(uv_it->second) : std::nullopt, where, data);
    if (!decoded) return decoded;
    // Strips and fans make up to one triangle per index: check the real count too.
    if (data.indices.size() / 3 > limits.max_faces - b.mesh.face_count())
        return make_error(ErrorCode::BudgetExceeded, where + ": " + std::to_string(data.indices.size() / 3) +
                                                         " more triangles exceed the limit of " +
                                                         std::to_string(limits.max_faces));
    if (data.texcoords.empty()) b.all_have_uvs = false;
    for (std::size_t k = 0; k < data.texcoords.size(); ++k)
        if (!std::isfinite(data.texcoords[k]))
            return make_error(ErrorCode::NonFinite,
                              where + ": TEXCOORD_0 of vertex " + std::to_string(k / 2) + " is not finite");
    return append_primitive(b, data, world, where);
}

//! Face-varying uvs with exact duplicates shared (the per-corner list would repeat every seam-free vertex).
void finish_uvs(Builder& b) {
    if (!b.all_have_uvs || b.uvs.empty()) return;
    std::unordered_map<PositionKey, Index, PositionKeyHash> seen;
    b.mesh.uv_indices.reserve(b.uvs.size());
    for (const Vec2& uv : b.uvs) {
        auto [it, inserted] = seen.try_emplace(key_of(Vec3{uv.x, uv.y, 0}), static_cast<Index>(b.mesh.uvs.size()));
        if (inserted) b.mesh.uvs.push_back(uv);
        b.mesh.uv_indices.push_back(it->second);
    }
}

//! Every triangle primitive of every mesh instance of the default scene, as one mesh.
Result<PolygonMesh> read_scene(const SceneInput& input, const ReadOptions& options, GltfReadReport& report) {
    std::vector<std::vector<unsigned char>> embedded;  // .gltf buffers, decoded; the document's views point here
    auto doc = parse_document(input, embedded);
    if (!doc) return doc.error();

    auto accessors = make_reader(*doc, input.kind);
    if (!accessors) return accessors.error();
    const MeshReader reader{*accessors, options};

    auto instances = collect_instances(*doc);
    if (!instances) return instances.error();

    // primitives
    Builder builder;
    for (const MeshInstance& inst : *instances) {
        const auto& primitives = doc->meshes[static_cast<std::size_t>(inst.mesh)];
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            const Primitive& prim = primitives[p];
            if (prim.mode != kModeTriangles && prim.mode != kModeTriangleStrip && prim.mode != kModeTriangleFan) {
                ++report.skipped_primitives;  // points and lines carry no surface
                continue;
            }
            if (Status s = add_primitive(reader, builder, prim, inst.world, static_cast<std::size_t>(inst.mesh), p); !s)
                return s.error();
        }
    }
    if (builder.mesh.face_count() == 0)
        return make_error(ErrorCode::Unsupported,
                          std::string(input.kind) + (report.skipped_primitives > 0
                                                         ? " has only point or line primitives, no triangles"
                                                         : " contains no triangles"));
    finish_uvs(builder);
    return std::move(builder.mesh);
}

//! A read guarded (gltf_document.h), the report reset first and keeping what the read counted.
template <class Read>
Result<PolygonMesh> guarded_with_report(const char* kind, GltfReadReport* report, Read&& read) {
    GltfReadReport local;
    GltfReadReport& counts = report ? *report : local;
    counts = GltfReadReport{};
    return guarded<PolygonMesh>(kind, [&] { return read(counts); });
}

}  // namespace

Result<PolygonMesh> read_glb(std::string_view bytes, const ReadOptions& options, GltfReadReport* report) {
    return guarded_with_report("GLB", report, [&](GltfReadReport& counts) -> Result<PolygonMesh> {
        auto input = glb_input(bytes);
        if (!input) return input.error();
        return read_scene(*input, options, counts);
    });
}

Result<PolygonMesh> read_gltf(std::string_view text, const ReadOptions& options, GltfReadReport* report) {
    return guarded_with_report("glTF", report,
                               [&](GltfReadReport& counts) { return read_scene(gltf_input(text), options, counts); });
}

}  // namespace surfaced
