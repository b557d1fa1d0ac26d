// Point clouds from glTF (gltf_points.h). Steps: the checked document (gltf_document.h) -> the primitives that give
// points (POINTS, else triangles) per mesh instance -> the counts their accessors announce against the limit, before
// anything is read -> each primitive's POSITION / NORMAL / COLOR_0 (accessors or Draco) -> world transform ->
// PointCloud.
#include "geometry/io/gltf_points.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "geometry/io/draco_points.h"
#include "geometry/io/gltf_document.h"

namespace surfaced {
namespace {

using namespace gltf_doc;

bool is_triangles(int mode) { return mode == kModeTriangles || mode == kModeTriangleStrip || mode == kModeTriangleFan; }

//! A primitive that gives points, with where it sits.
struct Selected {
    const Primitive* prim = nullptr;
    Mat4 world = kIdentity;
    std::string where;  //!< "meshes[m].primitives[p]"
    int position = -1;  //!< its POSITION accessor
};

//! One primitive's points as read, before the transform.
struct PrimitivePoints {
    std::vector<double> positions;  //!< 3 per point
    std::vector<double> normals;    //!< 3 per point, or empty
    std::vector<double> colors;     //!< color_components per point, or empty
    int color_components = 3;
};

std::string accessor_name(int index) { return "accessors[" + std::to_string(index) + "]"; }

//! POINTS primitives of every mesh instance, or, when there are none, the triangle primitives.
Result<std::vector<Selected>> select_primitives(const Document& doc, const std::vector<MeshInstance>& instances,
                                                GltfPointsReport& report) {
    bool any_points = false;
    for (const MeshInstance& inst : instances)
        for (const Primitive& prim : doc.meshes[static_cast<std::size_t>(inst.mesh)])
            any_points = any_points || prim.mode == kModePoints;
    std::vector<Selected> out;
    for (const MeshInstance& inst : instances) {
        const auto& primitives = doc.meshes[static_cast<std::size_t>(inst.mesh)];
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            const Primitive& prim = primitives[p];
            const bool take = any_points ? prim.mode == kModePoints : is_triangles(prim.mode);
            if (!take) {
                ++report.skipped_primitives;
                continue;
            }
            Selected s{&prim, inst.world,
                       "meshes[" + std::to_string(inst.mesh) + "].primitives[" + std::to_string(p) + "]"};
            const auto pos = prim.attributes.find("POSITION");
            if (pos == prim.attributes.end())
                return parse_error("glTF " + s.where + " has no POSITION", doc.json_offset);
            s.position = pos->second;
            ++(any_points ? report.point_primitives : report.triangle_primitives);
            out.push_back(std::move(s));
        }
    }
    return out;
}

//! The limit against what the accessors announce: every accessor to be read, and the points all primitives give.
Status check_announced_counts(const Document& doc, const std::vector<Selected>& selected, std::size_t max_points) {
    std::uint64_t total = 0;
    for (const Selected& s : selected) {
        const Primitive& prim = *s.prim;
        const std::uint64_t vertices = doc.accessors[static_cast<std::size_t>(s.position)].count;
        const bool indexed = prim.mode == kModePoints && prim.indices >= 0 && !prim.draco;
        const std::uint64_t points = indexed ? doc.accessors[static_cast<std::size_t>(prim.indices)].count : vertices;
        if (vertices > max_points || points > max_points || total > max_points - points)
            return make_error(ErrorCode::BudgetExceeded,
                              "glTF " + s.where + ": " + std::to_string(std::max(vertices, points)) +
                                  (total > 0 ? " more" : "") + " points exceed the limit of " +
                                  std::to_string(max_points));
        total += points;
    }
    return Ok{};
}

//! An attribute accessor's count against POSITION's, before it is read.
Status check_same_count(const Document& doc, const Selected& s, const char* semantic, int accessor) {
    const std::uint64_t count = doc.accessors[static_cast<std::size_t>(accessor)].count;
    const std::uint64_t positions = doc.accessors[static_cast<std::size_t>(s.position)].count;
    if (count == positions) return Ok{};
    return parse_error("glTF " + s.where + ": " + semantic + " (" + accessor_name(accessor) + ") has " +
                           std::to_string(count) + " elements, POSITION (" + accessor_name(s.position) + ") has " +
                           std::to_string(positions),
                       doc.json_offset);
}

//! COLOR_0 channels must be 0..1 (the glTF spec's range; also what PointCloud holds).
Status check_color_range(const Document& doc, const std::vector<double>& colors, int components,
                         const std::string& source) {
    for (std::size_t i = 0; i < colors.size(); ++i)
        if (!(colors[i] >= 0 && colors[i] <= 1))
            return parse_error("glTF " + source + " (COLOR_0): point " + std::to_string(i / components) +
                                   " has a channel " + std::to_string(colors[i]) + " outside 0..1",
                               doc.json_offset);
    return Ok{};
}

//! A plain primitive: its attributes read from their accessors (the indexed vertices, for indexed POINTS).
Status read_accessor_points(const Reader& reader, const Selected& s, PrimitivePoints& out) {
    const Document& doc = reader.doc;
    const Primitive& prim = *s.prim;
    const auto normal = prim.attributes.find("NORMAL");
    const auto color = prim.attributes.find("COLOR_0");
    if (normal != prim.attributes.end())
        if (Status st = check_same_count(doc, s, "NORMAL", normal->second); !st) return st;
    if (color != prim.attributes.end()) {
        if (Status st = check_same_count(doc, s, "COLOR_0", color->second); !st) return st;
        const int components = doc.accessors[static_cast<std::size_t>(color->second)].components;
        if (components != 3 && components != 4)
            return parse_error(
                "glTF " + s.where + ": COLOR_0 (" + accessor_name(color->second) + ") must be VEC3 or VEC4",
                doc.json_offset);
        out.color_components = components;
    }
    auto positions = reader.read_floats(s.position, 3, "POSITION");
    if (!positions) return positions.error();
    out.positions = std::move(*positions);
    if (normal != prim.attributes.end()) {
        auto normals = reader.read_floats(normal->second, 3, "NORMAL");
        if (!normals) return normals.error();
        out.normals = std::move(*normals);
    }
    if (color != prim.attributes.end()) {
        auto colors = reader.read_floats(color->second, out.color_components, "COLOR_0");
        if (!colors) return colors.error();
        if (Status st = check_color_range(doc, *colors, out.color_components, accessor_name(color->second)); !st)
            return st;
        out.colors = std::move(*colors);
    }
    if (prim.mode != kModePoints || prim.indices < 0) return Ok{};

    // indexed POINTS: the points are the vertices the indices name, in index order
    auto indices = reader.read_indices(prim.indices);
    if (!indices) return indices.error();
    const std::size_t vertices = out.positions.size() / 3;
    PrimitivePoints picked;
    picked.color_components = out.color_components;
    auto gather = [](const std::vector<double>& from, std::vector<double>& to, std::size_t v, std::size_t n) {
        if (!from.empty())
            to.insert(to.end(), from.begin() + static_cast<std::ptrdiff_t>(v * n),
                      from.begin() + static_cast<std::ptrdiff_t>((v + 1) * n));
    };
    for (std::size_t i = 0; i < indices->size(); ++i) {
        const std::size_t v = (*indices)[i];
        if (v >= vertices)
            return make_error(ErrorCode::IndexOutOfRange, "glTF " + s.where + ": index " + std::to_string(i) + " (" +
                                                              accessor_name(prim.indices) + ") refers to vertex " +
                                                              std::to_string(v) + " of " + std::to_string(vertices));
        gather(out.positions, picked.positions, v, 3);
        gather(out.normals, picked.normals, v, 3);
        gather(out.colors, picked.colors, v, static_cast<std::size_t>(out.color_components));
    }
    out = std::move(picked);
    return Ok{};
}

//! A KHR_draco_mesh_compression primitive (a Draco point cloud, or the points of a Draco mesh), within the points
//! left under the limit.
Status decode_draco_points(const Reader& reader, const Selected& s, std::size_t max_points, PrimitivePoints& out) {
    const Document& doc = reader.doc;
    const DracoPrimitive& draco = *s.prim->draco;
    draco_points::AttributeIds ids;
    const auto position = draco.attributes.find("POSITION");
    if (position == draco.attributes.end())
        return parse_error("glTF " + s.where + ": " + kDracoExtension + " has no POSITION attribute", doc.json_offset);
    ids.position = position->second;
    if (const auto normal = draco.attributes.find("NORMAL"); normal != draco.attributes.end())
        ids.normal = normal->second;
    if (const auto color = draco.attributes.find("COLOR_0"); color != draco.attributes.end()) ids.color = color->second;
    const auto bytes = doc.views[static_cast<std::size_t>(draco.buffer_view)].bytes;
    auto decoded = draco_points::decode({bytes.data(), bytes.size()}, ids, max_points);
    if (!decoded) {
        GeoError e = decoded.error();
        e.message = "glTF " + s.where + ": " + e.message;
        return e;
    }
    out.positions.assign(decoded->positions.begin(), decoded->positions.end());
    out.normals.assign(decoded->normals.begin(), decoded->normals.end());
    out.colors.assign(decoded->colors.begin(), decoded->colors.end());
    out.color_components = decoded->color_components;
    return check_color_range(doc, out.colors, out.color_components, s.where + " Draco data");
}

//! The 3x3 normal matrix of `m` (its inverse transpose up to a positive factor): columns b x c, c x a, a x b of
//! m's columns a, b, c, negated under a mirroring transform.
std::array<Vec3, 3> normal_matrix(const Mat4& m) {
    const Vec3 a{m[0], m[1], m[2]}, b{m[4], m[5], m[6]}, c{m[8], m[9], m[10]};
    const double sign = determinant3(m) < 0 ? -1.0 : 1.0;
    return {cross(b, c) * sign, cross(c, a) * sign, cross(a, b) * sign};
}

//! Accumulates the primitives' points; normals and colours only while every primitive has them.
struct Builder {
    PointCloud cloud;
    bool normals = true, colors = true;            //!< every primitive so far had usable ones
    bool saw_normals = false, saw_colors = false;  //!< some primitive had them
};

Status append(Builder& b, const PrimitivePoints& data, const Selected& s, GltfPointsReport& report) {
    const std::size_t count = data.positions.size() / 3;
    const Mat4& w = s.world;
    for (std::size_t v = 0; v < count; ++v) {
        const double x = data.positions[3 * v], y = data.positions[3 * v + 1], z = data.positions[3 * v + 2];
        const Vec3 p{w[0] * x + w[4] * y + w[8] * z + w[12], w[1] * x + w[5] * y + w[9] * z + w[13],
                     w[2] * x + w[6] * y + w[10] * z + w[14]};
        if (!is_finite(p))
            return make_error(ErrorCode::NonFinite,
                              "glTF " + s.where + ": point " + std::to_string(v) + " is not finite");
        b.cloud.positions.push_back(p);
    }

    // normals: kept while every primitive has usable ones
    b.saw_normals = b.saw_normals || !data.normals.empty();
    if (data.normals.empty()) b.normals = false;
    if (b.normals) {
        const auto nm = normal_matrix(w);
        for (std::size_t v = 0; v < count && b.normals; ++v) {
            const Vec3 n =
                nm[0] * data.normals[3 * v] + nm[1] * data.normals[3 * v + 1] + nm[2] * data.normals[3 * v + 2];
            const double len = norm(n);
            if (!(len > 0) || !std::isfinite(len)) {
                b.normals = false;
                break;
            }
            b.cloud.normals.push_back(n * (1.0 / len));
        }
    }
    if (!b.normals) b.cloud.normals.clear();

    // colours: kept while every primitive has them; VEC3 ones get alpha 1 beside VEC4 ones
    b.saw_colors = b.saw_colors || !data.colors.empty();
    if (data.colors.empty()) b.colors = false;
    if (b.colors) {
        const auto n = static_cast<std::size_t>(data.color_components);
        for (std::size_t v = 0; v < count; ++v) {
            const double* c = data.colors.data() + v * n;
            b.cloud.colors.push_back({static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]),
                                      n == 4 ? static_cast<float>(c[3]) : 1.0f});
        }
        b.cloud.has_alpha = b.cloud.has_alpha || n == 4;
    } else {
        b.cloud.colors.clear();
        b.cloud.has_alpha = false;
    }
    report.normals_dropped = b.saw_normals && !b.normals;
    report.colors_dropped = b.saw_colors && !b.colors;
    return Ok{};
}

Result<PointCloud> read_points_scene(const SceneInput& input, const PointReadOptions& options,
                                     GltfPointsReport& report) {
    std::vector<std::vector<unsigned char>> embedded;  // .gltf buffers, decoded; the document's views point here
    auto doc = parse_document(input, embedded);
    if (!doc) return doc.error();
    auto reader = make_reader(*doc, input.kind);
    if (!reader) return reader.error();
    auto instances = collect_instances(*doc);
    if (!instances) return instances.error();
    auto selected = select_primitives(*doc, *instances, report);
    if (!selected) return selected.error();
    if (selected->empty())
        return make_error(ErrorCode::Unsupported,
                          std::string(input.kind) + (report.skipped_primitives > 0
                                                         ? " has only line primitives, no points or triangles"
                                                         : " contains no mesh primitives"));
    if (Status s = check_announced_counts(*doc, *selected, options.max_points); !s) return s.error();

    Builder builder;
    for (const Selected& s : *selected) {
        PrimitivePoints data;
        Status read = s.prim->draco ? decode_draco_points(*reader, s, options.max_points - builder.cloud.size(), data)
                                    : read_accessor_points(*reader, s, data);
        if (!read) return read.error();
        if (Status st = append(builder, data, s, report); !st) return st.error();
    }
    if (builder.cloud.empty()) return make_error(ErrorCode::Unsupported, std::string(input.kind) + " holds no points");
    return std::move(builder.cloud);
}

template <class Read>
Result<PointCloud> guarded_with_report(const char* kind, GltfPointsReport* report, Read&& read) {
    GltfPointsReport local;
    GltfPointsReport& counts = report ? *report : local;
    counts = GltfPointsReport{};
    return guarded<PointCloud>(kind, [&] { return read(counts); });
}

}  // namespace

Result<PointCloud> read_glb_points(std::string_view bytes, const PointReadOptions& options, GltfPointsReport* report) {
    return guarded_with_report("GLB", report, [&](GltfPointsReport& counts) -> Result<PointCloud> {
        auto input = glb_input(bytes);
        if (!input) return input.error();
        return read_points_scene(*input, options, counts);
    });
}

Result<PointCloud> read_gltf_points(std::string_view text, const PointReadOptions& options, GltfPointsReport* report) {
    return guarded_with_report(
        "glTF", report, [&](GltfPointsReport& counts) { return read_points_scene(gltf_input(text), options, counts); });
}

}  // namespace surfaced
