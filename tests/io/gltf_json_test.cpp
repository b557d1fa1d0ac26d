// read_gltf: glTF JSON with base64-embedded buffers reads through the GLB's scene path (same meshes as the GLB of
// the same document), points and lines are skipped and counted, and anything not embedded is refused by name.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"
#include "tests/io/format_test_helpers.h"

namespace surfaced {
namespace {

using format_test::expect_same_mesh;
using format_test::fails_with;
using nlohmann::json;

constexpr int kFloat = 5126, kUnsignedShort = 5123;
constexpr int kPoints = 0, kTriangles = 4;

std::string base64(std::string_view bytes) {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t n = std::uint32_t(std::uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) n |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) n |= std::uint8_t(bytes[i + 2]);
        out += kAlphabet[(n >> 18) & 63];
        out += kAlphabet[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? kAlphabet[(n >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? kAlphabet[n & 63] : '=';
    }
    return out;
}

//! A GLB of `gltf` (whose buffer 0 has no uri) with `bin` as its BIN chunk.
std::string make_glb(const json& gltf, std::string bin) {
    std::string text = gltf.dump();
    while (text.size() % 4) text += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string out = "glTF";
    auto put = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };  // little-endian host
    put(2);
    put(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
    put(static_cast<std::uint32_t>(text.size()));
    put(0x4E4F534A);
    out += text;
    put(static_cast<std::uint32_t>(bin.size()));
    put(0x004E4942);
    out += bin;
    return out;
}

//! The same document as .gltf text: buffer 0 embedded as a data: URI.
std::string make_gltf(json gltf, std::string_view bin, std::string_view media_type = "application/octet-stream") {
    gltf["buffers"][0]["uri"] = "data:" + std::string(media_type) + ";base64," + base64(bin);
    return gltf.dump(1);
}

//! Unit cube [0,1]^3 by hand: 8 float positions (96 bytes) and 12 outward uint16 triangles (72 bytes).
struct HandCube {
    std::string bin;
    json gltf;
};

HandCube hand_cube() {
    const float p[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const std::uint16_t t[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                    {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    HandCube cube;
    cube.bin.append(reinterpret_cast<const char*>(p), sizeof p);
    cube.bin.append(reinterpret_cast<const char*>(t), sizeof t);
    cube.gltf = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes", {{{"mesh", 0}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
        {"accessors",
         {{{"bufferView", 0},
           {"componentType", kFloat},
           {"count", 8},
           {"type", "VEC3"},
           {"min", {0, 0, 0}},
           {"max", {1, 1, 1}}},
          {{"bufferView", 1}, {"componentType", kUnsignedShort}, {"count", 36}, {"type", "SCALAR"}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteLength", 96}}, {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 72}}}},
        {"buffers", {{{"byteLength", 168}}}}};
    return cube;
}

TEST(GltfJsonRead, HandWrittenCubeReadsLikeItsGlb) {
    const HandCube cube = hand_cube();
    auto from_glb = read_glb(make_glb(cube.gltf, cube.bin));
    ASSERT_TRUE(from_glb.ok()) << from_glb.error().message;
    for (const char* media_type : {"application/octet-stream", "application/gltf-buffer"}) {
        const std::string text = make_gltf(cube.gltf, cube.bin, media_type);
        auto from_gltf = read_gltf(text);
        ASSERT_TRUE(from_gltf.ok()) << from_gltf.error().message;
        EXPECT_EQ(from_gltf->vertex_count(), 8u);
        EXPECT_EQ(from_gltf->face_count(), 12u);
        expect_same_mesh(*from_glb, *from_gltf);
        EXPECT_EQ(sniff_format(text), MeshFormat::Gltf);
        auto dispatched = read_mesh(text, MeshFormat::Gltf);
        ASSERT_TRUE(dispatched.ok()) << dispatched.error().message;
        expect_same_mesh(*from_glb, *dispatched);
    }
    EXPECT_EQ(format_from_extension("scene.GLTF"), MeshFormat::Gltf);
    EXPECT_EQ(format_from_media_type("model/gltf+json; charset=utf-8"), MeshFormat::Gltf);
    EXPECT_EQ(sniff_format("  {\"asset\": {\"version\": \"2.0\"}}"), MeshFormat::Gltf);
    EXPECT_EQ(sniff_format("{\"mesh\": {}}"), std::nullopt);
}

TEST(GltfJsonRead, OurWritersGiveTheSameMeshAsGlbAndAsGltf) {
    for (bool draco : {true, false}) {
        GltfOptions options;
        options.draco = draco;
        const PolygonMesh cube = format_test::cube();
        auto glb = write_glb(cube, options);
        auto gltf = write_gltf(cube, options);
        ASSERT_TRUE(glb.ok() && gltf.ok());
        auto a = read_glb(*glb);
        auto b = read_gltf(*gltf);
        ASSERT_TRUE(a.ok()) << a.error().message;
        ASSERT_TRUE(b.ok()) << b.error().message;
        EXPECT_EQ(b->vertex_count(), 8u);
        expect_same_mesh(*a, *b);
    }
}

TEST(GltfJsonRead, NestedNodeTransforms) {
    HandCube cube = hand_cube();
    // parent: scale 2; child: translation (10, 0, 0) and the mesh. World = S * T: p -> 2 (p + t).
    cube.gltf["nodes"] =
        json::array({{{"children", {1}}, {"scale", {2, 2, 2}}}, {{"mesh", 0}, {"translation", {10, 0, 0}}}});
    auto mesh = read_gltf(make_gltf(cube.gltf, cube.bin));
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    ASSERT_EQ(mesh->vertex_count(), 8u);
    const PolygonMesh unit = format_test::cube();  // the same corner order as hand_cube()
    for (std::size_t v = 0; v < 8; ++v) EXPECT_EQ(mesh->positions[v], (unit.positions[v] + Vec3{10, 0, 0}) * 2.0);
}

TEST(GltfJsonRead, TwoMeshesSeveralPrimitivesPointsSkippedAndCounted) {
    HandCube cube = hand_cube();
    json& g = cube.gltf;
    // mesh 0: the cube's first 6 triangles, its last 6, and its corners as POINTS; mesh 1: the whole cube.
    g["accessors"].push_back({{"bufferView", 1}, {"componentType", kUnsignedShort}, {"count", 18}, {"type", "SCALAR"}});
    g["accessors"].push_back(
        {{"bufferView", 1}, {"byteOffset", 36}, {"componentType", kUnsignedShort}, {"count", 18}, {"type", "SCALAR"}});
    g["meshes"] = json::array({{{"primitives",
                                 {{{"attributes", {{"POSITION", 0}}}, {"indices", 2}, {"mode", kTriangles}},
                                  {{"attributes", {{"POSITION", 0}}}, {"indices", 3}},
                                  {{"attributes", {{"POSITION", 0}}}, {"mode", kPoints}}}}},
                               {{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}});
    g["nodes"] = json::array({{{"mesh", 0}}, {{"mesh", 1}, {"translation", {5, 0, 0}}}});
    g["scenes"][0]["nodes"] = {0, 1};
    GltfReadReport report;
    report.skipped_primitives = 99;  // reset by the reader
    auto mesh = read_gltf(make_gltf(g, cube.bin), {}, &report);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->vertex_count(), 16u);
    EXPECT_EQ(mesh->face_count(), 24u);
    EXPECT_EQ(report.skipped_primitives, 1u);
    // The same count from the GLB reader.
    GltfReadReport glb_report;
    auto from_glb = read_glb(make_glb(g, cube.bin), {}, &glb_report);
    ASSERT_TRUE(from_glb.ok()) << from_glb.error().message;
    expect_same_mesh(*from_glb, *mesh);
    EXPECT_EQ(glb_report.skipped_primitives, 1u);

    // Only points: an error that says so.
    g["meshes"] = json::array({{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"mode", kPoints}}}}}});
    g["nodes"] = json::array({{{"mesh", 0}}});
    g["scenes"][0]["nodes"] = {0};
    EXPECT_TRUE(fails_with(read_gltf(make_gltf(g, cube.bin)), ErrorCode::Unsupported, "only point or line"));
}

TEST(GltfJsonRead, ExternalBuffersAndImagesAreRefusedByName) {
    HandCube cube = hand_cube();
    json g = cube.gltf;
    g["buffers"][0]["uri"] = "mesh.bin";
    auto r = read_gltf(g.dump());
    EXPECT_TRUE(fails_with(r, ErrorCode::Unsupported,
                           "buffers[0].uri \"mesh.bin\" is an external file: embed the buffer (data: URI) or send a "
                           "GLB"));
    g["buffers"][0]["uri"] = "https://example.com/mesh.bin";
    EXPECT_TRUE(fails_with(read_gltf(g.dump()), ErrorCode::Unsupported, "\"https://example.com/mesh.bin\" is a URL"));
    g["buffers"][0].erase("uri");
    EXPECT_TRUE(fails_with(read_gltf(g.dump()), ErrorCode::ParseError, "buffers[0].uri is missing"));

    json with_image = json::parse(make_gltf(cube.gltf, cube.bin));
    with_image["images"] = json::array({{{"uri", "data:image/png;base64,iVBORw0KGgo="}}, {{"uri", "tex.png"}}});
    EXPECT_TRUE(fails_with(read_gltf(with_image.dump()), ErrorCode::Unsupported,
                           "images[1].uri \"tex.png\" is an external file"));
    with_image["images"].erase(1);
    EXPECT_TRUE(read_gltf(with_image.dump()).ok());  // an embedded image is ignored, as in a GLB
}

TEST(GltfJsonRead, BadBase64IsRefusedNamingTheBuffer) {
    const HandCube cube = hand_cube();
    const std::string good = "data:application/octet-stream;base64," + base64(cube.bin);
    auto with_uri = [&](const std::string& uri) {
        json g = cube.gltf;
        g["buffers"][0]["uri"] = uri;
        return read_gltf(g.dump());
    };
    ASSERT_TRUE(with_uri(good).ok());
    std::string bad_char = good;
    bad_char[40] = '*';
    EXPECT_TRUE(fails_with(with_uri(bad_char), ErrorCode::ParseError, "buffers[0].uri: base64 data has '*' at"));
    EXPECT_TRUE(
        fails_with(with_uri(good.substr(0, good.size() - 1)), ErrorCode::ParseError, "buffers[0].uri: base64 data of"));
    std::string early_padding = good;
    early_padding[45] = '=';
    EXPECT_TRUE(fails_with(with_uri(early_padding), ErrorCode::ParseError, "padding before the end"));
    EXPECT_TRUE(fails_with(with_uri("data:text/plain;base64," + base64(cube.bin)), ErrorCode::Unsupported,
                           "buffers[0].uri: data: URI has media type \"text/plain\""));
    EXPECT_TRUE(fails_with(with_uri("data:application/octet-stream,abc"), ErrorCode::Unsupported, "not base64"));
    // byteLength longer than the data.
    EXPECT_TRUE(fails_with(with_uri("data:application/octet-stream;base64," + base64(cube.bin.substr(0, 160))),
                           ErrorCode::ParseError, "buffers[0].byteLength = 168 exceeds its data: URI (160 bytes)"));
    // "xx==" with stray bits: not canonical base64.
    EXPECT_TRUE(fails_with(with_uri("data:application/octet-stream;base64,AB=="), ErrorCode::ParseError, "stray bits"));
}

TEST(GltfJsonRead, ErrorsAndLimits) {
    // JSON errors are located in the text itself (no GLB header before it).
    auto r = read_gltf("{\"asset\": }");
    ASSERT_TRUE(fails_with(r, ErrorCode::ParseError, "invalid glTF JSON at byte 10"));
    EXPECT_EQ(r.error().offset, 10);
    const HandCube cube = hand_cube();
    json g = cube.gltf;
    g["accessors"][0]["count"] = 9;
    r = read_gltf(make_gltf(g, cube.bin));
    ASSERT_TRUE(fails_with(r, ErrorCode::ParseError, "glTF accessors[0]"));
    EXPECT_EQ(r.error().offset, 0);
    EXPECT_TRUE(fails_with(read_gltf(std::string(make_glb(cube.gltf, cube.bin))), ErrorCode::ParseError,
                           "invalid glTF JSON at byte 0"));

    const std::string text = make_gltf(cube.gltf, cube.bin);
    ReadOptions few;
    few.max_vertices = 7;
    EXPECT_TRUE(fails_with(read_gltf(text, few), ErrorCode::BudgetExceeded, "limit of 7"));
    few = {};
    few.max_faces = 11;
    EXPECT_TRUE(fails_with(read_gltf(text, few), ErrorCode::BudgetExceeded, "limit of 11"));
}

TEST(GltfJsonRead, RandomMutationsNeverCrash) {
    // Any result is fine except a crash or a mesh that breaks the PolygonMesh invariants (fuzz_gltf_json goes further).
    std::mt19937 rng(11);
    for (bool draco : {true, false}) {
        GltfOptions options;
        options.draco = draco;
        auto good = write_gltf(format_test::cube(), options);
        ASSERT_TRUE(good.ok());
        for (int trial = 0; trial < 1000; ++trial) {
            std::string bad = *good;
            const int flips = 1 + static_cast<int>(rng() % 4);
            for (int k = 0; k < flips; ++k) bad[rng() % bad.size()] = static_cast<char>(rng());
            auto r = read_gltf(bad);
            if (r.ok()) {
                EXPECT_TRUE(validate(*r).ok()) << "trial " << trial;
            } else {
                EXPECT_FALSE(r.error().message.empty());
                EXPECT_NE(r.error().code, ErrorCode::Internal) << r.error().message;
            }
        }
    }
}

}  // namespace
}  // namespace surfaced
