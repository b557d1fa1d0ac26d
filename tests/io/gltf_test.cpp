// write_glb / read_glb: every GLB written here passes the Khronos validator (0 errors, 0 warnings; a validator that
// cannot run is a failure), Draco payloads are decoded with Draco's own decoder and compared within the
// quantization bound, uncompressed round trips are exact to float precision, and malformed GLBs give errors.
#include "geometry/io/gltf.h"

#include <draco/compression/decode.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>

#include "geometry/mesh/triangulate.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced {
namespace {

using nlohmann::json;

constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

// ---- meshes ---------------------------------------------------------------------------------------------------

// Unit cube centred at the origin, outward quads.
PolygonMesh make_cube() {
    PolygonMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({(i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5});
    m.add_face({0, 2, 3, 1});
    m.add_face({4, 5, 7, 6});
    m.add_face({0, 1, 5, 4});
    m.add_face({2, 6, 7, 3});
    m.add_face({0, 4, 6, 2});
    m.add_face({1, 3, 7, 5});
    return m;
}

// The cube with its own uv rectangle per face: every corner is on a uv seam (24 glTF vertices for 8 positions).
PolygonMesh make_uv_cube() {
    PolygonMesh m = make_cube();
    for (std::size_t f = 0; f < m.face_count(); ++f) {
        const double u0 = 0.125 * static_cast<double>(f), v0 = 0.0625 * static_cast<double>(f);
        const Index base = static_cast<Index>(m.uvs.size());
        m.uvs.insert(m.uvs.end(), {{u0, v0}, {u0 + 0.1, v0}, {u0 + 0.1, v0 + 0.3}, {u0, v0 + 0.3}});
        m.uv_indices.insert(m.uv_indices.end(), {base, base + 1, base + 2, base + 3});
    }
    return m;
}

// Icosahedron subdivided `levels` times and projected onto a sphere: closed, all triangles, outward.
PolygonMesh make_icosphere(int levels, double radius = 1.0) {
    const double t = (1 + std::sqrt(5.0)) / 2;
    PolygonMesh m;
    m.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<Index, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                               {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                               {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                               {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<Index, Index>, Index> mid;
        auto midpoint = [&](Index a, Index b) {
            auto key = std::minmax(a, b);
            auto [it, inserted] = mid.try_emplace({key.first, key.second}, static_cast<Index>(m.positions.size()));
            if (inserted) m.positions.push_back((m.positions[a] + m.positions[b]) * 0.5);
            return it->second;
        };
        std::vector<std::array<Index, 3>> next;
        for (auto [a, b, c] : faces) {
            const Index ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            next.insert(next.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
        }
        faces = std::move(next);
    }
    for (Vec3& p : m.positions) p *= radius / norm(p);
    for (auto [a, b, c] : faces) m.add_face({a, b, c});
    return m;
}

// (nx x ny) quads on [0, nx] x [0, ny], z a gentle bump so that the mesh is not flat.
PolygonMesh make_grid(int nx, int ny) {
    PolygonMesh m;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i)
            m.positions.push_back({double(i), double(j), std::sin(i * 0.1) * std::cos(j * 0.1)});
    auto at = [&](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) m.add_face({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    return m;
}

// ---- GLB plumbing -----------------------------------------------------------------------------------------------

struct GlbParts {
    json gltf;
    std::string bin;
};

std::uint32_t u32_at(std::string_view s, std::size_t offset) {
    std::uint32_t v;
    std::memcpy(&v, s.data() + offset, 4);
    return v;
}

// Splits a well-formed GLB (checks the layout on the way: this is also the test of the container we write).
GlbParts split_glb(std::string_view glb) {
    GlbParts parts;
    EXPECT_GE(glb.size(), 20u);
    if (glb.size() < 20) return parts;
    EXPECT_EQ(glb.substr(0, 4), "glTF");
    EXPECT_EQ(u32_at(glb, 4), 2u);
    EXPECT_EQ(u32_at(glb, 8), glb.size());
    const std::uint32_t json_length = u32_at(glb, 12);
    EXPECT_EQ(json_length % 4, 0u);
    EXPECT_EQ(u32_at(glb, 16), 0x4E4F534Au);
    parts.gltf = json::parse(glb.substr(20, json_length));
    const std::size_t bin_at = 20 + json_length;
    if (bin_at < glb.size()) {
        const std::uint32_t bin_length = u32_at(glb, bin_at);
        EXPECT_EQ(bin_length % 4, 0u);
        EXPECT_EQ(u32_at(glb, bin_at + 4), 0x004E4942u);
        EXPECT_EQ(bin_at + 8 + bin_length, glb.size());
        parts.bin = std::string(glb.substr(bin_at + 8, bin_length));
    }
    return parts;
}

std::string make_glb(const json& gltf, std::string bin) {
    std::string text = gltf.dump();
    while (text.size() % 4) text += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string out = "glTF";
    auto put = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    put(2);
    put(static_cast<std::uint32_t>(12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size())));
    put(static_cast<std::uint32_t>(text.size()));
    put(0x4E4F534A);
    out += text;
    if (!bin.empty()) {
        put(static_cast<std::uint32_t>(bin.size()));
        put(0x004E4942);
        out += bin;
    }
    return out;
}

void expect_valid_gltf(std::string_view glb) {
    const testing::GltfValidation v = testing::run_gltf_validator(glb);
    ASSERT_TRUE(v.ran) << v.report;
    EXPECT_EQ(v.errors, 0) << v.report;
    EXPECT_EQ(v.warnings, 0) << v.report;
}

std::string write_ok(const PolygonMesh& mesh, const GltfOptions& options = {}) {
    auto glb = write_glb(mesh, options);
    EXPECT_TRUE(glb.ok()) << (glb.ok() ? "" : glb.error().message);
    return glb.ok() ? *glb : std::string();
}

GltfOptions plain() {
    GltfOptions o;
    o.draco = false;
    return o;
}

// ---- Draco decoding with Draco's own decoder ----------------------------------------------------------------------

struct DecodedDraco {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;
    std::vector<Vec2> texcoords;
    std::vector<std::array<Index, 3>> triangles;
};

std::vector<float> attribute_values(const draco::Mesh& mesh, int unique_id, int components) {
    const draco::PointAttribute* att = mesh.GetAttributeByUniqueId(static_cast<std::uint32_t>(unique_id));
    EXPECT_NE(att, nullptr) << "no Draco attribute with unique id " << unique_id;
    if (att == nullptr) return {};
    EXPECT_EQ(att->num_components(), components);
    std::vector<float> out(mesh.num_points() * static_cast<std::size_t>(components));
    for (draco::PointIndex p(0); p < mesh.num_points(); ++p)
        EXPECT_TRUE(att->ConvertValue<float>(att->mapped_index(p), static_cast<std::int8_t>(components),
                                             out.data() + p.value() * static_cast<std::size_t>(components)));
    return out;
}

// Decodes the primitive's KHR_draco_mesh_compression payload and checks the accessors against it.
DecodedDraco decode_draco(const GlbParts& parts) {
    DecodedDraco out;
    const json& prim = parts.gltf["meshes"][0]["primitives"][0];
    const json& ext = prim["extensions"]["KHR_draco_mesh_compression"];
    const json& view = parts.gltf["bufferViews"][ext["bufferView"].get<int>()];
    const std::size_t offset = view.value("byteOffset", 0);
    const std::size_t length = view["byteLength"];
    EXPECT_LE(offset + length, parts.bin.size());
    draco::DecoderBuffer buffer;
    buffer.Init(parts.bin.data() + offset, length);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    EXPECT_TRUE(decoded.ok()) << decoded.status().error_msg();
    if (!decoded.ok()) return out;
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();

    const json& accessors = parts.gltf["accessors"];
    const json& attributes = prim["attributes"];
    // Accessor counts must describe the decoded data.
    EXPECT_EQ(accessors[attributes["POSITION"].get<int>()]["count"].get<std::size_t>(), mesh->num_points());
    EXPECT_EQ(accessors[prim["indices"].get<int>()]["count"].get<std::size_t>(), 3 * std::size_t{mesh->num_faces()});

    const auto pos = attribute_values(*mesh, ext["attributes"]["POSITION"], 3);
    for (std::size_t i = 0; i + 2 < pos.size(); i += 3) out.positions.push_back({pos[i], pos[i + 1], pos[i + 2]});
    if (ext["attributes"].contains("NORMAL")) {
        const auto n = attribute_values(*mesh, ext["attributes"]["NORMAL"], 3);
        for (std::size_t i = 0; i + 2 < n.size(); i += 3) out.normals.push_back({n[i], n[i + 1], n[i + 2]});
    }
    if (ext["attributes"].contains("TEXCOORD_0")) {
        const auto t = attribute_values(*mesh, ext["attributes"]["TEXCOORD_0"], 2);
        for (std::size_t i = 0; i + 1 < t.size(); i += 2) out.texcoords.push_back({t[i], t[i + 1]});
    }
    for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
        const auto& face = mesh->face(f);
        out.triangles.push_back({face[0].value(), face[1].value(), face[2].value()});
    }
    return out;
}

// Draco quantizes all three axes over one range (the largest extent) into 2^bits - 1 steps and rounds to the
// nearest step, so the error per axis is half a step; float arithmetic on coordinates of magnitude M adds a few ulps.
double position_bound(const PolygonMesh& mesh, int bits) {
    const Box3 box = mesh.bounds();
    double range = 0, magnitude = 0;
    for (int k = 0; k < 3; ++k) {
        range = std::max(range, box.max[k] - box.min[k]);
        magnitude = std::max({magnitude, std::fabs(box.min[k]), std::fabs(box.max[k])});
    }
    return 0.5 * range / double((1u << bits) - 1) + 4 * FLT_EPSILON * magnitude;
}

// Rotation-invariant key of a triangle (keeps orientation: (a,b,c) ~ (b,c,a) but not (a,c,b)).
std::array<Index, 3> canonical(std::array<Index, 3> t) {
    while (t[0] != std::min({t[0], t[1], t[2]})) t = {t[1], t[2], t[0]};
    return t;
}

std::multiset<std::array<Index, 3>> triangle_set(const PolygonMesh& tri) {
    std::multiset<std::array<Index, 3>> set;
    for (std::size_t f = 0; f < tri.face_count(); ++f)
        set.insert(canonical({tri.face(f)[0], tri.face(f)[1], tri.face(f)[2]}));
    return set;
}

// Matches decoded points to the original vertices (nearest, within the bound) and checks that the decoded
// triangles are the original ones with the same orientation.
void expect_draco_matches(const PolygonMesh& original, const DecodedDraco& decoded, int bits) {
    const double bound = position_bound(original, bits);
    ASSERT_EQ(decoded.positions.size(), original.vertex_count());
    std::vector<Index> match(decoded.positions.size());
    std::vector<int> hits(original.vertex_count(), 0);
    double worst = 0;
    for (std::size_t p = 0; p < decoded.positions.size(); ++p) {
        std::size_t best = 0;
        double best_d = INFINITY;
        for (std::size_t v = 0; v < original.vertex_count(); ++v) {
            const double d = norm(decoded.positions[p] - original.positions[v]);
            if (d < best_d) best_d = d, best = v;
        }
        for (int k = 0; k < 3; ++k) {
            const double err = std::fabs(decoded.positions[p][k] - original.positions[best][k]);
            worst = std::max(worst, err);
            EXPECT_LE(err, bound) << "point " << p << " axis " << k << " (" << bits << " bits)";
        }
        match[p] = static_cast<Index>(best);
        ++hits[best];
    }
    for (std::size_t v = 0; v < hits.size(); ++v) EXPECT_EQ(hits[v], 1) << "original vertex " << v;
    std::multiset<std::array<Index, 3>> got;
    for (auto t : decoded.triangles) got.insert(canonical({match[t[0]], match[t[1]], match[t[2]]}));
    EXPECT_EQ(got, triangle_set(triangulate(original)));
    ::testing::Test::RecordProperty("worst_error_" + std::to_string(bits), std::to_string(worst));
}

void expect_error(const Result<PolygonMesh>& r, ErrorCode code, const char* what) {
    ASSERT_FALSE(r.ok()) << what;
    EXPECT_EQ(r.error().code, code) << what << ": " << r.error().message;
    EXPECT_FALSE(r.error().message.empty()) << what;
}

// ---- writer: Draco -----------------------------------------------------------------------------------------------

TEST(GltfWrite, DracoCubeIsValidAndWellFormed) {
    const PolygonMesh cube = make_cube();
    const std::string glb = write_ok(cube);
    expect_valid_gltf(glb);
    const GlbParts parts = split_glb(glb);
    const json& g = parts.gltf;
    EXPECT_EQ(g["asset"]["version"], "2.0");
    EXPECT_EQ(g["asset"]["generator"], "surfaced");
    EXPECT_EQ(g["extensionsUsed"], json::array({"KHR_draco_mesh_compression"}));
    EXPECT_EQ(g["extensionsRequired"], json::array({"KHR_draco_mesh_compression"}));
    ASSERT_EQ(g["scenes"].size(), 1u);
    ASSERT_EQ(g["nodes"].size(), 1u);
    ASSERT_EQ(g["meshes"].size(), 1u);
    ASSERT_EQ(g["meshes"][0]["primitives"].size(), 1u);
    const json& prim = g["meshes"][0]["primitives"][0];
    EXPECT_EQ(prim["mode"], 4);
    EXPECT_FALSE(prim["attributes"].contains("NORMAL"));  // off by default
    for (const json& a : g["accessors"]) EXPECT_FALSE(a.contains("bufferView")) << a.dump();
    EXPECT_EQ(g["accessors"][prim["indices"].get<int>()]["componentType"], kUnsignedShort);

    const DecodedDraco decoded = decode_draco(parts);
    expect_draco_matches(cube, decoded, GltfOptions{}.quantize_position);
    // POSITION min/max are those of the decoded data.
    const json& pos = g["accessors"][prim["attributes"]["POSITION"].get<int>()];
    ASSERT_EQ(pos["min"].size(), 3u);
    ASSERT_EQ(pos["max"].size(), 3u);
    EXPECT_EQ(pos["componentType"], kFloat);
    EXPECT_EQ(pos["type"], "VEC3");
    for (int k = 0; k < 3; ++k) {
        double lo = INFINITY, hi = -INFINITY;
        for (const Vec3& p : decoded.positions) lo = std::min(lo, p[k]), hi = std::max(hi, p[k]);
        EXPECT_EQ(pos["min"][k].get<double>(), lo);
        EXPECT_EQ(pos["max"][k].get<double>(), hi);
    }
}

// The JSON of a GLB and of a text glTF prints numbers as every text output does: accessor bounds of -0 and 1 as
// "0" and "1" (tinygltf alone writes -0.0 and 1.0).
TEST(GltfWrite, JsonNumbersAreShortestWithoutNegativeZero) {
    PolygonMesh mesh;
    mesh.positions = {{-0.0, -0.0, -0.0}, {1, -0.0, 0.5}, {-0.0, 1, -0.0}};
    mesh.add_face({0, 1, 2});
    GltfOptions options;
    options.draco = false;
    const std::string glb = write_ok(mesh, options);
    expect_valid_gltf(glb);
    const GlbParts parts = split_glb(glb);
    const std::string chunk(glb.substr(20, u32_at(glb, 12)));
    auto text = write_gltf(mesh, options);
    ASSERT_TRUE(text.ok()) << text.error().message;
    for (const std::string& json_text : {chunk, *text}) {
        EXPECT_NE(json_text.find(R"("max":[1,1,0.5])"), std::string::npos) << json_text.substr(0, 400);
        EXPECT_NE(json_text.find(R"("min":[0,0,0])"), std::string::npos) << json_text.substr(0, 400);
        EXPECT_EQ(json_text.find("-0"), std::string::npos) << json_text.substr(0, 400);
        EXPECT_EQ(json_text.find(".0,"), std::string::npos) << json_text.substr(0, 400);
        EXPECT_EQ(json_text.find(".0]"), std::string::npos) << json_text.substr(0, 400);
    }
    EXPECT_EQ(parts.gltf["accessors"][0]["count"], 3);
}

TEST(GltfWrite, DracoPositionsWithinQuantizationBound) {
    const PolygonMesh sphere = make_icosphere(2, 3.0);
    for (int bits : {8, 11, 14, 20, 24}) {
        SCOPED_TRACE("quantize_position " + std::to_string(bits));
        GltfOptions options;
        options.quantize_position = bits;
        const std::string glb = write_ok(sphere, options);
        expect_draco_matches(sphere, decode_draco(split_glb(glb)), bits);
    }
}

TEST(GltfWrite, DracoQuantizationExtremesAreAccepted) {
    const PolygonMesh sphere = make_icosphere(1);
    // The largest accepted values are capped below Draco's 30 bits (see gltf_write.cpp: cost doubles per bit).
    for (int bits : {1, 24}) {
        GltfOptions options;
        options.quantize_position = bits;
        options.quantize_normal = bits == 1 ? 2 : 22;
        options.quantize_texcoord = bits;
        options.normals = true;
        auto glb = write_glb(sphere, options);
        ASSERT_TRUE(glb.ok()) << bits << ": " << glb.error().message;
        expect_valid_gltf(*glb);
        EXPECT_TRUE(read_glb(*glb).ok()) << bits;
    }
}

TEST(GltfWrite, DracoWithNormalsAndTexcoords) {
    const PolygonMesh cube = make_uv_cube();
    GltfOptions options;
    options.normals = true;
    const std::string glb = write_ok(cube, options);
    expect_valid_gltf(glb);
    const GlbParts parts = split_glb(glb);
    const json& attributes = parts.gltf["meshes"][0]["primitives"][0]["attributes"];
    EXPECT_TRUE(attributes.contains("NORMAL"));
    EXPECT_TRUE(attributes.contains("TEXCOORD_0"));
    const DecodedDraco decoded = decode_draco(parts);
    ASSERT_EQ(decoded.positions.size(), 24u);  // split at the uv seams: 8 corners x 3 faces
    ASSERT_EQ(decoded.normals.size(), 24u);
    ASSERT_EQ(decoded.texcoords.size(), 24u);
    const double uv_bound = 0.5 / double((1u << options.quantize_texcoord) - 1) + 4 * FLT_EPSILON;
    std::set<std::pair<double, double>> written_uvs;
    for (const Vec2& uv : cube.uvs) written_uvs.insert({uv.x, 1.0 - uv.y});  // glTF's v axis points down
    for (std::size_t p = 0; p < 24; ++p) {
        // Octahedral quantization at 10 bits keeps normals unit length and close to the cube's corner diagonal.
        EXPECT_NEAR(norm(decoded.normals[p]), 1.0, 1e-3);
        EXPECT_GT(dot(decoded.normals[p], decoded.positions[p]), 0.99 * norm(decoded.positions[p]));
        bool near_written = false;
        for (auto [u, v] : written_uvs)
            near_written = near_written || (std::fabs(decoded.texcoords[p].x - u) <= uv_bound &&
                                            std::fabs(decoded.texcoords[p].y - v) <= uv_bound);
        EXPECT_TRUE(near_written) << "uv " << decoded.texcoords[p].x << ", " << decoded.texcoords[p].y;
    }
}

TEST(GltfWrite, LargeMeshUsesUnsignedIntIndices) {
    // 257 x 257 = 66049 vertices: index 65535 is needed, and it is UNSIGNED_SHORT's primitive-restart value.
    const PolygonMesh grid = make_grid(256, 256);
    for (bool draco : {true, false}) {
        SCOPED_TRACE(draco ? "draco" : "plain");
        GltfOptions options;
        options.draco = draco;
        const std::string glb = write_ok(grid, options);
        expect_valid_gltf(glb);
        const GlbParts parts = split_glb(glb);
        const json& prim = parts.gltf["meshes"][0]["primitives"][0];
        EXPECT_EQ(parts.gltf["accessors"][prim["indices"].get<int>()]["componentType"], kUnsignedInt);
        auto back = read_glb(glb);
        ASSERT_TRUE(back.ok()) << back.error().message;
        EXPECT_EQ(back->vertex_count(), grid.vertex_count());
        EXPECT_EQ(back->face_count(), 2 * grid.face_count());
    }
    // Just below the limit: 65535 vertices still fit UNSIGNED_SHORT.
    PolygonMesh strip = make_grid(65533 / 2, 1);  // 2 x 32767 = 65534 vertices
    const GlbParts parts = split_glb(write_ok(strip, plain()));
    const json& prim = parts.gltf["meshes"][0]["primitives"][0];
    EXPECT_EQ(parts.gltf["accessors"][prim["indices"].get<int>()]["componentType"], kUnsignedShort);
}

// ---- writer: uncompressed ------------------------------------------------------------------------------------------

TEST(GltfWrite, PlainBufferViewsAreAlignedAndTargeted) {
    GltfOptions options = plain();
    options.normals = true;
    const std::string glb = write_ok(make_uv_cube(), options);
    expect_valid_gltf(glb);
    const GlbParts parts = split_glb(glb);
    const json& g = parts.gltf;
    EXPECT_FALSE(g.contains("extensionsUsed"));
    EXPECT_FALSE(g.contains("extensionsRequired"));
    const json& prim = g["meshes"][0]["primitives"][0];
    for (const char* name : {"POSITION", "NORMAL", "TEXCOORD_0"}) {
        const json& a = g["accessors"][prim["attributes"][name].get<int>()];
        EXPECT_EQ(a["componentType"], kFloat) << name;
        EXPECT_EQ(a["count"], 24) << name;
        const json& view = g["bufferViews"][a["bufferView"].get<int>()];
        EXPECT_EQ(view["target"], kArrayBuffer) << name;
        EXPECT_EQ(view.value("byteOffset", 0) % 4, 0) << name;
    }
    const json& indices = g["accessors"][prim["indices"].get<int>()];
    EXPECT_EQ(g["bufferViews"][indices["bufferView"].get<int>()]["target"], kElementArrayBuffer);
    EXPECT_EQ(indices["count"], 36);
    EXPECT_EQ(g["buffers"][0]["byteLength"].get<std::size_t>(), parts.bin.size());
}

TEST(GltfRoundTrip, PlainIsExactToFloatPrecision) {
    // Coordinates that are not exactly representable as float, far from the origin.
    PolygonMesh mesh = make_icosphere(2, 1.2345678901);
    for (Vec3& p : mesh.positions) p += Vec3{1000.1, -20.2, 3.3};
    const std::string glb = write_ok(mesh, plain());
    expect_valid_gltf(glb);
    auto back = read_glb(glb);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->vertex_count(), mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        for (int k = 0; k < 3; ++k)
            EXPECT_EQ(back->positions[v][k], double(float(mesh.positions[v][k]))) << "vertex " << v;
    EXPECT_EQ(back->face_indices, triangulate(mesh).face_indices);
    EXPECT_FALSE(back->has_uvs());
}

TEST(GltfRoundTrip, PlainQuadCubeWithUvSeamsWeldsBackToEightVertices) {
    const PolygonMesh cube = make_uv_cube();
    const std::string glb = write_ok(cube, plain());
    auto back = read_glb(glb);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->vertex_count(), 8u);
    EXPECT_EQ(back->face_count(), 12u);
    EXPECT_TRUE(testing::is_watertight(*back));
    EXPECT_EQ(back->positions, cube.positions);  // exactly representable coordinates
    const PolygonMesh expected = triangulate(cube);
    EXPECT_EQ(back->face_indices, expected.face_indices);
    ASSERT_TRUE(back->has_uvs());
    ASSERT_EQ(back->uv_indices.size(), expected.uv_indices.size());
    for (std::size_t c = 0; c < expected.uv_indices.size(); ++c) {
        const Vec2 want = expected.uvs[expected.uv_indices[c]];
        const Vec2 got = back->uvs[back->uv_indices[c]];
        EXPECT_NEAR(got.x, want.x, 1e-7) << "corner " << c;
        EXPECT_NEAR(got.y, want.y, 1e-7) << "corner " << c;
    }
    EXPECT_TRUE(validate(*back).ok());
}

TEST(GltfRoundTrip, TexcoordsCanBeSwitchedOff) {
    GltfOptions options = plain();
    options.texcoords = false;
    const GlbParts parts = split_glb(write_ok(make_uv_cube(), options));
    const json& attributes = parts.gltf["meshes"][0]["primitives"][0]["attributes"];
    EXPECT_FALSE(attributes.contains("TEXCOORD_0"));
    EXPECT_EQ(parts.gltf["accessors"][attributes["POSITION"].get<int>()]["count"], 8);  // no seams to split
}

TEST(GltfRoundTrip, DracoKeepsVertexCountOfClosedMeshes) {
    for (const PolygonMesh& mesh : {make_cube(), make_uv_cube(), make_icosphere(3)}) {
        const std::string glb = write_ok(mesh);
        auto back = read_glb(glb);
        ASSERT_TRUE(back.ok()) << back.error().message;
        EXPECT_EQ(back->vertex_count(), mesh.vertex_count());
        EXPECT_EQ(back->face_count(), triangulate(mesh).face_count());
        EXPECT_TRUE(testing::is_watertight(*back));
        EXPECT_GT(testing::signed_volume(*back), 0);  // still outward
        EXPECT_EQ(back->has_uvs(), mesh.has_uvs());
        const double bound = position_bound(mesh, GltfOptions{}.quantize_position);
        for (const Vec3& p : back->positions) {
            double best = INFINITY;
            for (const Vec3& q : mesh.positions)
                best = std::min(best, std::max({std::fabs(p.x - q.x), std::fabs(p.y - q.y), std::fabs(p.z - q.z)}));
            EXPECT_LE(best, bound);
        }
    }
}

TEST(GltfWrite, NormalsAreUnitAndOutward) {
    // Uncompressed: the validator itself checks that every NORMAL is unit length.
    const PolygonMesh sphere = make_icosphere(2);
    GltfOptions options = plain();
    options.normals = true;
    const std::string glb = write_ok(sphere, options);
    expect_valid_gltf(glb);
    const GlbParts parts = split_glb(glb);
    const json& g = parts.gltf;
    const json& a = g["accessors"][g["meshes"][0]["primitives"][0]["attributes"]["NORMAL"].get<int>()];
    const json& view = g["bufferViews"][a["bufferView"].get<int>()];
    const std::size_t offset = view.value("byteOffset", 0);
    ASSERT_EQ(a["count"].get<std::size_t>(), sphere.vertex_count());
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
        float n[3];
        std::memcpy(n, parts.bin.data() + offset + 12 * v, 12);
        const Vec3 normal{n[0], n[1], n[2]};
        EXPECT_NEAR(norm(normal), 1.0, 1e-6);
        EXPECT_GT(dot(normal, sphere.positions[v]), 0.98);
    }
    // Draco: the same after octahedral quantization.
    options.draco = true;
    const DecodedDraco decoded = decode_draco(split_glb(write_ok(sphere, options)));
    ASSERT_EQ(decoded.normals.size(), decoded.positions.size());
    for (std::size_t p = 0; p < decoded.normals.size(); ++p) {
        EXPECT_NEAR(norm(decoded.normals[p]), 1.0, 1e-3);
        EXPECT_GT(dot(decoded.normals[p], decoded.positions[p]), 0.97);
    }
}

TEST(GltfWrite, MeshNormalsAreNormalisedBeforeWriting) {
    PolygonMesh cube = make_cube();
    for (const Vec3& p : cube.positions) cube.normals.push_back(p * 7.0);  // not unit length
    cube.normals[3] = Vec3{};                                              // no direction at all
    GltfOptions options = plain();
    options.normals = true;
    expect_valid_gltf(write_ok(cube, options));
}

TEST(GltfWrite, RejectsBadOptionsAndMeshes) {
    const PolygonMesh cube = make_cube();
    auto expect_invalid = [&](GltfOptions o, const char* what) {
        auto r = write_glb(cube, o);
        ASSERT_FALSE(r.ok()) << what;
        EXPECT_EQ(r.error().code, ErrorCode::InvalidArgument) << what;
        EXPECT_FALSE(r.error().message.empty());
    };
    GltfOptions o;
    o.quantize_position = 0;
    expect_invalid(o, "position 0");
    o = {};
    o.quantize_position = 25;
    expect_invalid(o, "position 25");
    o = {};
    o.quantize_position = 31;
    expect_invalid(o, "position 31");
    o = {};
    o.quantize_normal = 1;
    expect_invalid(o, "normal 1");
    o = {};
    o.quantize_normal = 23;  // Draco's normal encoder cost explodes beyond this (see gltf_write.cpp)
    expect_invalid(o, "normal 23");
    o = {};
    o.quantize_texcoord = 25;
    expect_invalid(o, "texcoord 25");
    o = {};
    o.encode_speed = -1;
    expect_invalid(o, "encode speed -1");
    o = {};
    o.decode_speed = 11;
    expect_invalid(o, "decode speed 11");

    auto empty = write_glb(PolygonMesh{});
    ASSERT_FALSE(empty.ok());
    EXPECT_EQ(empty.error().code, ErrorCode::InvalidArgument);
    PolygonMesh no_faces;
    no_faces.positions = {{0, 0, 0}};
    ASSERT_FALSE(write_glb(no_faces).ok());

    PolygonMesh broken = make_cube();
    broken.face_indices[5] = 42;
    auto r = write_glb(broken);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::IndexOutOfRange);
    PolygonMesh nan = make_cube();
    nan.positions[0].x = NAN;
    ASSERT_FALSE(write_glb(nan, plain()).ok());
}

// ---- reader: scene graph --------------------------------------------------------------------------------------

TEST(GltfRead, AppliesNodeTransforms) {
    const PolygonMesh cube = make_cube();
    GlbParts parts = split_glb(write_ok(cube, plain()));
    // parent: translate (10, 0, 0); child: scale 2 and the mesh.
    parts.gltf["nodes"] =
        json::array({{{"children", {1}}, {"translation", {10, 0, 0}}}, {{"mesh", 0}, {"scale", {2, 2, 2}}}});
    parts.gltf["scenes"][0]["nodes"] = {0};
    auto back = read_glb(make_glb(parts.gltf, parts.bin));
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->vertex_count(), 8u);
    for (std::size_t v = 0; v < 8; ++v) EXPECT_EQ(back->positions[v], (cube.positions[v] * 2.0 + Vec3{10, 0, 0}));

    // A matrix node (column-major) rotating 90 degrees about z.
    parts.gltf["nodes"] = json::array({{{"mesh", 0}, {"matrix", {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}}});
    back = read_glb(make_glb(parts.gltf, parts.bin));
    ASSERT_TRUE(back.ok()) << back.error().message;
    for (std::size_t v = 0; v < 8; ++v) {
        const Vec3 p = cube.positions[v];
        EXPECT_EQ(back->positions[v], (Vec3{-p.y, p.x, p.z}));
    }
}

TEST(GltfRead, MirroringTransformKeepsMeshOutward) {
    GlbParts parts = split_glb(write_ok(make_cube(), plain()));
    parts.gltf["nodes"][0]["scale"] = {-1, 1, 1};
    auto back = read_glb(make_glb(parts.gltf, parts.bin));
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(testing::is_watertight(*back));
    EXPECT_GT(testing::signed_volume(*back), 0);
}

TEST(GltfRead, EveryInstanceOfAMeshIsRead) {
    GlbParts parts = split_glb(write_ok(make_cube()));  // Draco: two instances decode the same payload
    parts.gltf["nodes"] = json::array({{{"mesh", 0}}, {{"mesh", 0}, {"translation", {5, 0, 0}}}});
    parts.gltf["scenes"][0]["nodes"] = {0, 1};
    auto back = read_glb(make_glb(parts.gltf, parts.bin));
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->vertex_count(), 16u);
    EXPECT_EQ(back->face_count(), 24u);
    EXPECT_TRUE(testing::is_watertight(*back));
}

TEST(GltfRead, NonIndexedTriangleSoupIsWelded) {
    // A tetrahedron as 4 separate triangles (12 vertices, no indices), as STL-like exporters write it.
    const std::vector<Vec3> corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int tris[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    std::string bin;
    for (auto& t : tris)
        for (int c : t)
            for (int k = 0; k < 3; ++k) {
                const float f = static_cast<float>(corners[static_cast<std::size_t>(c)][k]);
                bin.append(reinterpret_cast<const char*>(&f), 4);
            }
    json g = {{"asset", {{"version", "2.0"}}},
              {"scene", 0},
              {"scenes", {{{"nodes", {0}}}}},
              {"nodes", {{{"mesh", 0}}}},
              {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
              {"accessors",
               {{{"bufferView", 0},
                 {"componentType", kFloat},
                 {"count", 12},
                 {"type", "VEC3"},
                 {"min", {0, 0, 0}},
                 {"max", {1, 1, 1}}}}},
              {"bufferViews", {{{"buffer", 0}, {"byteLength", 144}}}},
              {"buffers", {{{"byteLength", 144}}}}};
    const std::string glb = make_glb(g, bin);
    expect_valid_gltf(glb);  // the hand-made input is itself valid glTF
    auto back = read_glb(glb);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->vertex_count(), 4u);
    EXPECT_EQ(back->face_count(), 4u);
    EXPECT_TRUE(testing::is_watertight(*back));
    EXPECT_GT(testing::signed_volume(*back), 0);
}

TEST(GltfRead, LimitsApplyBeforeDecoding) {
    for (bool draco : {true, false}) {
        GltfOptions options;
        options.draco = draco;
        const std::string glb = write_ok(make_cube(), options);
        ReadOptions few_vertices;
        few_vertices.max_vertices = 7;
        auto r = read_glb(glb, few_vertices);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().code, ErrorCode::BudgetExceeded);
        ReadOptions few_faces;
        few_faces.max_faces = 11;
        r = read_glb(glb, few_faces);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().code, ErrorCode::BudgetExceeded);
        ReadOptions exact;
        exact.max_vertices = 8;
        exact.max_faces = 12;
        EXPECT_TRUE(read_glb(glb, exact).ok());
    }
}

TEST(GltfRead, StripsAndFansBecomeTriangles) {
    // A square as a strip (0 1 2 3 zig-zag) and as a fan (0 1 2 3 around): both give two +z triangles.
    auto square = [](int mode, const std::vector<std::array<float, 3>>& pts) {
        std::string bin(reinterpret_cast<const char*>(pts.data()), pts.size() * 12);
        json g = {{"asset", {{"version", "2.0"}}},
                  {"scene", 0},
                  {"scenes", {{{"nodes", {0}}}}},
                  {"nodes", {{{"mesh", 0}}}},
                  {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"mode", mode}}}}}}},
                  {"accessors",
                   {{{"bufferView", 0},
                     {"componentType", kFloat},
                     {"count", pts.size()},
                     {"type", "VEC3"},
                     {"min", {0, 0, 0}},
                     {"max", {1, 1, 0}}}}},
                  {"bufferViews", {{{"buffer", 0}, {"byteLength", bin.size()}}}},
                  {"buffers", {{{"byteLength", bin.size()}}}}};
        return make_glb(g, bin);
    };
    for (auto [mode, pts] :
         {std::pair{5, std::vector<std::array<float, 3>>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}},
          std::pair{6, std::vector<std::array<float, 3>>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}}}) {
        SCOPED_TRACE("mode " + std::to_string(mode));
        auto back = read_glb(square(mode, pts));
        ASSERT_TRUE(back.ok()) << back.error().message;
        ASSERT_EQ(back->face_count(), 2u);
        for (std::size_t f = 0; f < 2; ++f) {
            auto t = back->face(f);
            EXPECT_GT(
                cross(back->positions[t[1]] - back->positions[t[0]], back->positions[t[2]] - back->positions[t[0]]).z,
                0);
        }
        EXPECT_EQ(testing::edge_stats(*back).inconsistent_edges, 0u);
    }
    // Lines only: nothing to read.
    expect_error(read_glb(square(1, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}})), ErrorCode::Unsupported,
                 "lines only");
}

TEST(GltfRead, MeshQuantizationIntegerPositions) {
    // KHR_mesh_quantization: int16 positions (stride 8 keeps each element 4-byte aligned) scaled by the node.
    const std::vector<std::array<std::int16_t, 3>> corners = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}};
    std::string bin;
    for (const auto& c : corners) {
        bin.append(reinterpret_cast<const char*>(c.data()), 6);
        bin.append(2, '\0');
    }
    const std::uint16_t idx[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    bin.append(reinterpret_cast<const char*>(idx), sizeof idx);
    json g = {{"asset", {{"version", "2.0"}}},
              {"extensionsUsed", {"KHR_mesh_quantization"}},
              {"extensionsRequired", {"KHR_mesh_quantization"}},
              {"scene", 0},
              {"scenes", {{{"nodes", {0}}}}},
              {"nodes", {{{"mesh", 0}, {"scale", {0.25, 0.25, 0.25}}}}},
              {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
              {"accessors",
               {{{"bufferView", 0},
                 {"componentType", 5122},
                 {"count", 4},
                 {"type", "VEC3"},
                 {"min", {0, 0, 0}},
                 {"max", {2, 2, 2}}},
                {{"bufferView", 1}, {"componentType", kUnsignedShort}, {"count", 12}, {"type", "SCALAR"}}}},
              {"bufferViews",
               {{{"buffer", 0}, {"byteLength", 32}, {"byteStride", 8}, {"target", kArrayBuffer}},
                {{"buffer", 0}, {"byteOffset", 32}, {"byteLength", 24}, {"target", kElementArrayBuffer}}}},
              {"buffers", {{{"byteLength", 56}}}}};
    const std::string glb = make_glb(g, bin);
    expect_valid_gltf(glb);
    auto back = read_glb(glb);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->vertex_count(), 4u);
    EXPECT_EQ(back->positions[1], (Vec3{0.5, 0, 0}));
    EXPECT_TRUE(testing::is_watertight(*back));
    EXPECT_GT(testing::signed_volume(*back), 0);

    // Without the extension, integer positions are not glTF 2.0.
    g.erase("extensionsUsed");
    g.erase("extensionsRequired");
    expect_error(read_glb(make_glb(g, bin)), ErrorCode::Unsupported, "integer positions without the extension");
}

TEST(GltfMalformed, NonFiniteValues) {
    GlbParts parts = split_glb(write_ok(make_uv_cube(), plain()));
    const json& prim = parts.gltf["meshes"][0]["primitives"][0];
    for (const char* semantic : {"POSITION", "TEXCOORD_0"}) {
        const json& a = parts.gltf["accessors"][prim["attributes"][semantic].get<int>()];
        const std::size_t at = parts.gltf["bufferViews"][a["bufferView"].get<int>()].value("byteOffset", 0);
        std::string bin = parts.bin;
        const float nan = std::numeric_limits<float>::quiet_NaN();
        std::memcpy(bin.data() + at + 4, &nan, 4);
        expect_error(read_glb(make_glb(parts.gltf, bin)), ErrorCode::NonFinite, semantic);
    }
}

TEST(GltfRead, JsonPaddedWithNulBytes) {
    // Some exporters pad the JSON chunk with NUL instead of spaces; accept it.
    const GlbParts parts = split_glb(write_ok(make_cube(), plain()));
    std::string text = parts.gltf.dump();
    text += '\0';
    while (text.size() % 4) text += '\0';
    std::string glb = "glTF";
    auto put = [&](std::uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    put(2);
    put(static_cast<std::uint32_t>(28 + text.size() + parts.bin.size()));
    put(static_cast<std::uint32_t>(text.size()));
    put(0x4E4F534A);
    glb += text;
    put(static_cast<std::uint32_t>(parts.bin.size()));
    put(0x004E4942);
    glb += parts.bin;
    auto back = read_glb(glb);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->vertex_count(), 8u);
}

// ---- reader: malformed input --------------------------------------------------------------------------------------

TEST(GltfMalformed, EveryTruncationIsAnError) {
    for (bool draco : {true, false}) {
        GltfOptions options;
        options.draco = draco;
        const std::string glb = write_ok(make_uv_cube(), options);
        for (std::size_t n = 0; n < glb.size(); ++n) {
            auto r = read_glb(std::string_view(glb).substr(0, n));
            ASSERT_FALSE(r.ok()) << "prefix of " << n << " bytes";
            EXPECT_EQ(r.error().code, ErrorCode::ParseError) << n;
        }
        EXPECT_TRUE(read_glb(glb).ok());
    }
}

TEST(GltfMalformed, HeaderAndChunkErrorsNameTheOffset) {
    const std::string good = write_ok(make_cube());
    auto patch = [&](std::size_t offset, std::uint32_t value) {
        std::string bad = good;
        std::memcpy(bad.data() + offset, &value, 4);
        return bad;
    };
    auto r = read_glb("solid cube\nfacet normal 0 0 1\n");
    expect_error(r, ErrorCode::ParseError, "not a GLB");
    EXPECT_EQ(r.error().offset, 0);

    r = read_glb(patch(0, 0x12345678));
    expect_error(r, ErrorCode::ParseError, "bad magic");
    EXPECT_EQ(r.error().offset, 0);

    r = read_glb(patch(4, 1));
    expect_error(r, ErrorCode::Unsupported, "version 1");
    EXPECT_EQ(r.error().offset, 4);

    r = read_glb(patch(8, static_cast<std::uint32_t>(good.size() + 4)));
    expect_error(r, ErrorCode::ParseError, "length beyond the input");
    EXPECT_EQ(r.error().offset, 8);

    r = read_glb(patch(12, 0xFFFFFFF0u));
    expect_error(r, ErrorCode::ParseError, "JSON chunk length");
    EXPECT_EQ(r.error().offset, 12);

    r = read_glb(patch(12, 0));
    expect_error(r, ErrorCode::ParseError, "empty JSON chunk");

    r = read_glb(patch(16, 0x004E4942));
    expect_error(r, ErrorCode::ParseError, "first chunk not JSON");
    EXPECT_EQ(r.error().offset, 16);

    const std::size_t bin_at = 20 + u32_at(good, 12);
    // BIN chunk claiming 8 bytes more than there are: exactly the case tinygltf 2.7.0's own check lets through.
    r = read_glb(patch(bin_at, u32_at(good, bin_at) + 8));
    expect_error(r, ErrorCode::ParseError, "BIN chunk length");
    EXPECT_EQ(r.error().offset, static_cast<std::int64_t>(bin_at));

    r = read_glb(patch(bin_at, 6));
    expect_error(r, ErrorCode::ParseError, "unaligned BIN chunk");
}

TEST(GltfMalformed, BadJson) {
    const GlbParts parts = split_glb(write_ok(make_cube()));
    std::string text = "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [";  // cut off
    // Replace the JSON chunk by hand (make_glb only takes valid JSON).
    while (text.size() % 4) text += ' ';
    std::string bad = "glTF";
    auto put = [&](std::uint32_t v) { bad.append(reinterpret_cast<const char*>(&v), 4); };
    put(2);
    put(static_cast<std::uint32_t>(20 + text.size()));
    put(static_cast<std::uint32_t>(text.size()));
    put(0x4E4F534A);
    bad += text;
    auto r = read_glb(bad);
    expect_error(r, ErrorCode::ParseError, "truncated JSON");
    // The offset points into the JSON chunk, at or after the point where the text stops making sense.
    EXPECT_GE(r.error().offset, 20 + 40);
    EXPECT_LE(r.error().offset, static_cast<std::int64_t>(20 + text.size()));

    r = read_glb(make_glb(json::object(), parts.bin));
    ASSERT_FALSE(r.ok()) << "no asset";
    r = read_glb(make_glb(json::array({1, 2, 3}), parts.bin));
    ASSERT_FALSE(r.ok()) << "JSON array";
}

TEST(GltfMalformed, AccessorAndViewOutOfRange) {
    const GlbParts parts = split_glb(write_ok(make_cube(), plain()));
    const json& prim = parts.gltf["meshes"][0]["primitives"][0];
    const int pos = prim["attributes"]["POSITION"];
    const int idx = prim["indices"];
    auto with = [&](auto&& edit) {
        json g = parts.gltf;
        edit(g);
        return read_glb(make_glb(g, parts.bin));
    };
    expect_error(with([&](json& g) { g["accessors"][pos]["count"] = 1000000; }), ErrorCode::ParseError, "count");
    expect_error(with([&](json& g) { g["accessors"][pos]["byteOffset"] = 4; }), ErrorCode::ParseError, "byteOffset");
    expect_error(with([&](json& g) { g["accessors"][pos]["byteOffset"] = 1ull << 62; }), ErrorCode::ParseError,
                 "huge byteOffset");
    expect_error(with([&](json& g) { g["accessors"][idx]["count"] = 300; }), ErrorCode::ParseError, "index count");
    auto r = with([&](json& g) { g["accessors"][pos]["bufferView"] = 99; });
    expect_error(r, ErrorCode::ParseError, "view index");
    EXPECT_NE(r.error().message.find("accessors[" + std::to_string(pos) + "].bufferView"), std::string::npos)
        << r.error().message;
    expect_error(with([&](json& g) { g["bufferViews"][0]["byteLength"] = 1u << 20; }), ErrorCode::ParseError,
                 "view length");
    expect_error(with([&](json& g) { g["bufferViews"][0]["byteStride"] = 4; }), ErrorCode::ParseError, "stride");
    expect_error(with([&](json& g) { g["accessors"][pos]["type"] = "VEC2"; }), ErrorCode::ParseError, "type");
    expect_error(with([&](json& g) { g["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 42; }),
                 ErrorCode::ParseError, "missing accessor");
    expect_error(with([&](json& g) { g["nodes"][0]["mesh"] = 3; }), ErrorCode::ParseError, "missing mesh");
    expect_error(with([&](json& g) { g["buffers"][0]["byteLength"] = 1u << 24; }), ErrorCode::ParseError,
                 "buffer longer than BIN");
    expect_error(with([&](json& g) { g["extensionsRequired"] = {"EXT_unknown"}; }), ErrorCode::Unsupported,
                 "required extension");
    expect_error(with([&](json& g) {
                     g["nodes"] = json::array({{{"children", {1}}}, {{"children", {0}}, {"mesh", 0}}});
                 }),
                 ErrorCode::ParseError, "node cycle");
    expect_error(with([&](json& g) { g["nodes"][0]["children"] = {0}; }), ErrorCode::ParseError,
                 "node is its own child");
    expect_error(with([&](json& g) { g["nodes"][0]["matrix"] = {1, 2, 3}; }), ErrorCode::ParseError, "short matrix");
    expect_error(with([&](json& g) { g["accessors"][pos]["count"] = -1; }), ErrorCode::ParseError, "negative count");
    expect_error(with([&](json& g) { g["accessors"][pos]["count"] = "8"; }), ErrorCode::ParseError, "string count");
    expect_error(with([&](json& g) { g["accessors"][idx]["componentType"] = kFloat; }), ErrorCode::ParseError,
                 "float indices");
    expect_error(with([&](json& g) { g["meshes"][0]["primitives"][0]["indices"] = -3; }), ErrorCode::ParseError,
                 "negative indices");
    expect_error(with([&](json& g) { g["meshes"] = json::object(); }), ErrorCode::ParseError, "meshes not an array");
}

TEST(GltfMalformed, IndexOutOfRange) {
    GlbParts parts = split_glb(write_ok(make_cube(), plain()));
    const json& prim = parts.gltf["meshes"][0]["primitives"][0];
    const json& idx = parts.gltf["accessors"][prim["indices"].get<int>()];
    ASSERT_EQ(idx["componentType"], kUnsignedShort);
    const std::size_t at = parts.gltf["bufferViews"][idx["bufferView"].get<int>()].value("byteOffset", 0);
    const std::uint16_t bad = 8;  // one past the last vertex
    std::memcpy(parts.bin.data() + at + 2 * 7, &bad, 2);
    auto r = read_glb(make_glb(parts.gltf, parts.bin));
    expect_error(r, ErrorCode::IndexOutOfRange, "index 8 of 8 vertices");
    EXPECT_EQ(r.error().element, 2);  // the corner sits in triangle 2
}

TEST(GltfMalformed, ExternalBufferUriIsRefused) {
    GlbParts parts = split_glb(write_ok(make_cube(), plain()));
    json g = parts.gltf;
    g["buffers"][0]["uri"] = "../../etc/passwd";
    auto r = read_glb(make_glb(g, parts.bin));
    expect_error(r, ErrorCode::Unsupported, "external uri");
    EXPECT_NE(r.error().message.find("../../etc/passwd"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("external"), std::string::npos) << r.error().message;
}

TEST(GltfMalformed, CorruptDracoPayloadIsAnErrorNotACrash) {
    GlbParts parts = split_glb(write_ok(make_icosphere(2)));
    const json& ext = parts.gltf["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"];
    const json& view = parts.gltf["bufferViews"][ext["bufferView"].get<int>()];
    const std::size_t offset = view.value("byteOffset", 0), length = view["byteLength"];
    // Header garbage must fail; garbage further in may or may not decode, but must never crash or give an
    // invalid mesh.
    std::string bin = parts.bin;
    for (std::size_t i = 0; i < 8; ++i) bin[offset + i] = '\x55';
    expect_error(read_glb(make_glb(parts.gltf, bin)), ErrorCode::ParseError, "Draco header");
    std::mt19937 rng(7);
    for (int trial = 0; trial < 300; ++trial) {
        bin = parts.bin;
        for (int k = 0; k < 4; ++k) bin[offset + rng() % length] = static_cast<char>(rng());
        auto r = read_glb(make_glb(parts.gltf, bin));
        if (r.ok()) {
            EXPECT_TRUE(validate(*r).ok()) << "trial " << trial;
        }
    }
    // A Draco attribute id that does not exist.
    json g = parts.gltf;
    g["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] = 7;
    expect_error(read_glb(make_glb(g, parts.bin)), ErrorCode::ParseError, "missing Draco attribute");
}

TEST(GltfMalformed, RandomMutationsNeverCrash) {
    // Byte-level fuzzing of whole files (header, JSON and BIN): any result is fine except a crash or a mesh that
    // breaks the PolygonMesh invariants.
    std::mt19937 rng(42);
    for (bool draco : {true, false}) {
        GltfOptions options;
        options.draco = draco;
        options.normals = true;
        const std::string good = write_ok(make_uv_cube(), options);
        for (int trial = 0; trial < 1500; ++trial) {
            std::string bad = good;
            const int flips = 1 + static_cast<int>(rng() % 4);
            for (int k = 0; k < flips; ++k) bad[rng() % bad.size()] = static_cast<char>(rng());
            auto r = read_glb(bad);
            if (r.ok()) {
                EXPECT_TRUE(validate(*r).ok()) << "trial " << trial;
            }
        }
    }
}

}  // namespace
}  // namespace surfaced
