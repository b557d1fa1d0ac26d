// Point clouds read from glTF (gltf_points.h): what write_points_glb writes reads back (plain exactly, Draco within
// its quantization), hand-built GLBs for what our writer never writes (node transforms on positions and normals,
// normalised byte colours, indexed POINTS, a mesh's vertices), and malformed input naming the accessor at fault.
// Also write_glb's vertex colours (COLOR_0), checked by the Khronos validator and read back as the mesh's points.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/io/draco_points.h"
#include "geometry/io/gltf.h"
#include "geometry/io/gltf_points.h"
#include "geometry/io/pointcloud_glb.h"
#include "geometry/io/pointcloud_io.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/pointcloud/kd_tree.h"
#include "tests/support/gltf_validator.h"

namespace surfaced {
namespace {

using nlohmann::json;

PointCloud sample_cloud(std::size_t n, bool alpha, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-2, 2);
    std::uniform_int_distribution<int> byte(0, 255);
    PointCloud cloud;
    cloud.has_alpha = alpha;
    for (std::size_t i = 0; i < n; ++i) {
        // float-exact coordinates, so that the plain round trip is exact
        cloud.positions.push_back({static_cast<float>(u(rng)), static_cast<float>(u(rng)), static_cast<float>(u(rng))});
        const Vec3 nrm{u(rng), u(rng), u(rng) + 0.01};
        cloud.normals.push_back(nrm * (1.0 / norm(nrm)));
        cloud.colors.push_back(
            {byte(rng) / 255.0f, byte(rng) / 255.0f, byte(rng) / 255.0f, alpha ? byte(rng) / 255.0f : 1.0f});
    }
    return cloud;
}

//! A GLB from a glTF JSON document and the bytes of its buffer 0.
std::string make_glb(json gltf, const std::string& bin) {
    if (!bin.empty()) gltf["buffers"] = json::array({{{"byteLength", bin.size()}}});
    std::string text = gltf.dump();
    text.resize((text.size() + 3) & ~std::size_t{3}, ' ');
    std::string padded = bin;
    padded.resize((padded.size() + 3) & ~std::size_t{3}, '\0');
    std::string out;
    auto u32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    out += "glTF";
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + text.size() + (padded.empty() ? 0 : 8 + padded.size())));
    u32(static_cast<std::uint32_t>(text.size()));
    out += "JSON";
    out += text;
    if (!padded.empty()) {
        u32(static_cast<std::uint32_t>(padded.size()));
        out += std::string("BIN\0", 4);
        out += padded;
    }
    return out;
}

template <class T>
void append(std::string& bin, std::initializer_list<T> values) {
    for (T v : values) bin.append(reinterpret_cast<const char*>(&v), sizeof v);
}

json accessor(int view, int component_type, const char* type, std::size_t count, bool normalized = false) {
    json a = {{"bufferView", view}, {"componentType", component_type}, {"type", type}, {"count", count}};
    if (normalized) a["normalized"] = true;
    return a;
}

json view(std::size_t offset, std::size_t length) {
    return {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}};
}

//! Three points: float positions, float normals, normalised unsigned-byte RGBA colours, in one node with `node`'s
//! transform members.
std::string three_points(const json& node) {
    std::string bin;
    append<float>(bin, {0, 0, 0, 1, 0, 0, 0, 2, 0});                           // POSITION at 0
    append<float>(bin, {0, 0, 1, 1, 0, 0, 0, 1, 0});                           // NORMAL at 36
    append<std::uint8_t>(bin, {255, 0, 0, 255, 0, 51, 0, 255, 0, 0, 255, 0});  // COLOR_0 at 72
    json gltf = {
        {"asset", {{"version", "2.0"}}},
        {"bufferViews", {view(0, 36), view(36, 36), view(72, 12)}},
        {"accessors", {accessor(0, 5126, "VEC3", 3), accessor(1, 5126, "VEC3", 3), accessor(2, 5121, "VEC4", 3, true)}},
        {"meshes",
         {{{"primitives", {{{"mode", 0}, {"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"COLOR_0", 2}}}}}}}}},
        {"nodes", {node}},
        {"scenes", {{{"nodes", {0}}}}},
        {"scene", 0}};
    return make_glb(gltf, bin);
}

void expect_near(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_LT(norm(a - b), tol) << "(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y << ", "
                                << b.z << ")";
}

TEST(GltfPoints, PlainGlbAndGltfReadBackExactly) {
    for (bool alpha : {false, true}) {
        const PointCloud cloud = sample_cloud(200, alpha, 3);
        auto glb = write_points_glb(cloud, {.draco = false});
        ASSERT_TRUE(glb.ok()) << glb.error().message;
        auto gltf = gltf_from_glb(*glb);
        ASSERT_TRUE(gltf.ok()) << gltf.error().message;
        for (const auto& read : {read_glb_points(*glb), read_gltf_points(*gltf), read_points(*glb, PointFormat::Glb),
                                 read_points(*gltf, PointFormat::Gltf)}) {
            ASSERT_TRUE(read.ok()) << read.error().message;
            ASSERT_EQ(read->size(), cloud.size());
            EXPECT_EQ(read->positions, cloud.positions);
            ASSERT_EQ(read->normals.size(), cloud.size());
            ASSERT_EQ(read->colors.size(), cloud.size());
            EXPECT_EQ(read->has_alpha, alpha);
            for (std::size_t i = 0; i < cloud.size(); ++i) {
                expect_near(read->normals[i], cloud.normals[i], 1e-6);  // float32 in the file
                EXPECT_EQ(read->colors[i].r, cloud.colors[i].r);
                EXPECT_EQ(read->colors[i].g, cloud.colors[i].g);
                EXPECT_EQ(read->colors[i].b, cloud.colors[i].b);
                EXPECT_EQ(read->colors[i].a, cloud.colors[i].a);
            }
        }
    }
}

TEST(GltfPoints, DracoGlbReadsBackWithinQuantization) {
    const int bits = 14;
    for (bool with_colors : {false, true}) {
        PointCloud cloud = sample_cloud(1500, true, 7);
        if (!with_colors) {
            cloud.colors.clear();
            cloud.has_alpha = false;
        }
        auto glb = write_points_glb(cloud, {.draco = true, .quantize_position = bits});
        ASSERT_TRUE(glb.ok()) << glb.error().message;
        GltfPointsReport report;
        auto read = read_glb_points(*glb, {}, &report);
        ASSERT_TRUE(read.ok()) << read.error().message;
        EXPECT_EQ(report.point_primitives, 1u);
        ASSERT_EQ(read->size(), cloud.size());
        ASSERT_EQ(read->normals.size(), cloud.size());
        ASSERT_EQ(read->colors.size(), with_colors ? cloud.size() : 0u);
        EXPECT_EQ(read->has_alpha, with_colors);
        // Draco may reorder the points: match each to the nearest original, within half a quantization step of
        // the largest extent
        const Box3 box = cloud.bounds();
        double extent = 0;
        for (int k = 0; k < 3; ++k) extent = std::max(extent, box.max[k] - box.min[k]);
        const double step = extent / ((1 << bits) - 1);
        const KdTree tree(cloud.positions);
        std::vector<Neighbor> nearest;
        std::vector<char> used(cloud.size(), 0);
        for (std::size_t p = 0; p < read->size(); ++p) {
            tree.knn(read->positions[p], 1, nearest);
            const std::size_t i = nearest[0].index;
            EXPECT_FALSE(used[i]) << "two points match original " << i;
            used[i] = 1;
            for (int k = 0; k < 3; ++k)
                EXPECT_LE(std::fabs(read->positions[p][k] - cloud.positions[i][k]), 0.5 * step + 1e-6);
            EXPECT_NEAR(norm(read->normals[p]), 1.0, 1e-12);
            EXPECT_GT(dot(read->normals[p], cloud.normals[i]), std::cos(0.01));
            if (with_colors) {
                EXPECT_NEAR(read->colors[p].r, cloud.colors[i].r, 0.5 / 255 + 1e-6);  // 8-bit in Draco
                EXPECT_NEAR(read->colors[p].a, cloud.colors[i].a, 0.5 / 255 + 1e-6);
            }
        }
    }
}

TEST(GltfPoints, NodeTransformMovesPointsAndTurnsNormals) {
    // translate (10, 0, 0), scale (2, 1, -1): a mirror, so normals go through the inverse transpose and stay outward
    auto read = read_glb_points(three_points({{"mesh", 0}, {"translation", {10, 0, 0}}, {"scale", {2, 1, -1}}}));
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->size(), 3u);
    expect_near(read->positions[0], {10, 0, 0}, 1e-12);
    expect_near(read->positions[1], {12, 0, 0}, 1e-12);
    expect_near(read->positions[2], {10, 2, 0}, 1e-12);
    expect_near(read->normals[0], {0, 0, -1}, 1e-12);
    expect_near(read->normals[1], {1, 0, 0}, 1e-12);
    expect_near(read->normals[2], {0, 1, 0}, 1e-12);
    // normalised unsigned bytes: 255 -> 1, 51 -> 0.2
    ASSERT_TRUE(read->has_alpha);
    EXPECT_EQ(read->colors[0].r, 1.0f);
    EXPECT_FLOAT_EQ(read->colors[1].g, 0.2f);
    EXPECT_EQ(read->colors[2].a, 0.0f);
    // a non-uniform scale: the normal (1, 1, 0)/sqrt2 on the plane x + y = c becomes (1, 2, 0)/sqrt5 under x *= 2
    std::string bin;
    append<float>(bin, {0, 0, 0, 0.70710678f, 0.70710678f, 0});
    json gltf = {{"asset", {{"version", "2.0"}}},
                 {"bufferViews", {view(0, 12), view(12, 12)}},
                 {"accessors", {accessor(0, 5126, "VEC3", 1), accessor(1, 5126, "VEC3", 1)}},
                 {"meshes", {{{"primitives", {{{"mode", 0}, {"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}}}}}}},
                 {"nodes", {{{"mesh", 0}, {"scale", {2, 1, 1}}}}}};
    auto sheared = read_glb_points(make_glb(gltf, bin));
    ASSERT_TRUE(sheared.ok()) << sheared.error().message;
    expect_near(sheared->normals[0], Vec3{1, 2, 0} * (1 / std::sqrt(5.0)), 1e-6);
}

TEST(GltfPoints, IndexedPointsAreTheIndexedVertices) {
    std::string bin;
    append<float>(bin, {0, 0, 0, 1, 0, 0, 0, 1, 0});
    append<std::uint16_t>(bin, {2, 0, 2, 0});  // the last two bytes pad
    json gltf = {{"asset", {{"version", "2.0"}}},
                 {"bufferViews", {view(0, 36), view(36, 6)}},
                 {"accessors", {accessor(0, 5126, "VEC3", 3), accessor(1, 5123, "SCALAR", 3)}},
                 {"meshes", {{{"primitives", {{{"mode", 0}, {"indices", 1}, {"attributes", {{"POSITION", 0}}}}}}}}}};
    auto read = read_glb_points(make_glb(gltf, bin));
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->size(), 3u);
    expect_near(read->positions[0], {0, 1, 0}, 1e-15);
    expect_near(read->positions[1], {0, 0, 0}, 1e-15);
    expect_near(read->positions[2], {0, 1, 0}, 1e-15);
    EXPECT_FALSE(read->has_normals());
    // an index past the vertices
    bin.replace(36, 2, std::string("\x07\x00", 2));
    auto bad = read_glb_points(make_glb(gltf, bin));
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().code, ErrorCode::IndexOutOfRange);
    EXPECT_NE(bad.error().message.find("refers to vertex 7 of 3"), std::string::npos) << bad.error().message;
}

TEST(GltfPoints, ATriangleMeshGivesItsVerticesWithTheirNormals) {
    // a tetrahedron written with vertex normals (plain and Draco): its four vertices, each normal pointing outward
    PolygonMesh tet;
    tet.positions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    tet.add_face({0, 1, 2});
    tet.add_face({0, 3, 1});
    tet.add_face({0, 2, 3});
    tet.add_face({1, 3, 2});
    for (bool draco : {false, true}) {
        auto glb = write_glb(tet, {.draco = draco, .normals = true});
        ASSERT_TRUE(glb.ok()) << glb.error().message;
        GltfPointsReport report;
        auto read = read_glb_points(*glb, {}, &report);
        ASSERT_TRUE(read.ok()) << read.error().message;
        EXPECT_EQ(report.point_primitives, 0u);
        EXPECT_EQ(report.triangle_primitives, 1u);
        ASSERT_EQ(read->size(), 4u);
        ASSERT_TRUE(read->has_normals());
        for (std::size_t i = 0; i < 4; ++i) {
            // the vertex normal of a regular tetrahedron points away from the centre, along the position
            EXPECT_GT(dot(read->normals[i], read->positions[i] * (1 / norm(read->positions[i]))), 0.999);
        }
    }
}

TEST(GltfPoints, PointsWinOverTrianglesAndLinesAreSkipped) {
    std::string bin;
    append<float>(bin, {0, 0, 0, 1, 0, 0, 0, 1, 0});
    json gltf = {{"asset", {{"version", "2.0"}}},
                 {"bufferViews", {view(0, 36)}},
                 {"accessors", {accessor(0, 5126, "VEC3", 3)}},
                 {"meshes",
                  {{{"primitives",
                     {{{"mode", 4}, {"attributes", {{"POSITION", 0}}}},
                      {{"mode", 0}, {"attributes", {{"POSITION", 0}}}},
                      {{"mode", 1}, {"attributes", {{"POSITION", 0}}}}}}}}}};
    GltfPointsReport report;
    auto read = read_glb_points(make_glb(gltf, bin), {}, &report);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read->size(), 3u);
    EXPECT_EQ(report.point_primitives, 1u);
    EXPECT_EQ(report.skipped_primitives, 2u);
    // lines only: nothing to read
    gltf["meshes"][0]["primitives"] = json::array({{{"mode", 1}, {"attributes", {{"POSITION", 0}}}}});
    auto lines = read_glb_points(make_glb(gltf, bin));
    ASSERT_FALSE(lines.ok());
    EXPECT_EQ(lines.error().code, ErrorCode::Unsupported);
    EXPECT_NE(lines.error().message.find("only line primitives"), std::string::npos) << lines.error().message;
}

TEST(GltfPoints, MixedAttributesKeepOnlyWhatEveryPrimitiveHas) {
    std::string bin;
    append<float>(bin, {0, 0, 0, 0, 0, 1, 1, 0, 0});  // POSITION, NORMAL, POSITION
    json gltf = {
        {"asset", {{"version", "2.0"}}},
        {"bufferViews", {view(0, 12), view(12, 12), view(24, 12)}},
        {"accessors", {accessor(0, 5126, "VEC3", 1), accessor(1, 5126, "VEC3", 1), accessor(2, 5126, "VEC3", 1)}},
        {"meshes",
         {{{"primitives",
            {{{"mode", 0}, {"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}},
             {{"mode", 0}, {"attributes", {{"POSITION", 2}}}}}}}}}};
    GltfPointsReport report;
    auto read = read_glb_points(make_glb(gltf, bin), {}, &report);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read->size(), 2u);
    EXPECT_FALSE(read->has_normals());
    EXPECT_TRUE(report.normals_dropped);
}

TEST(GltfPoints, MalformedInputNamesTheAccessor) {
    auto expect_error = [](const std::string& glb, ErrorCode code, const std::string& needle) {
        auto read = read_glb_points(glb);
        ASSERT_FALSE(read.ok()) << needle;
        EXPECT_EQ(read.error().code, code) << read.error().message;
        EXPECT_NE(read.error().message.find(needle), std::string::npos) << read.error().message;
    };
    const std::string good = three_points({{"mesh", 0}});
    ASSERT_TRUE(read_glb_points(good).ok());
    auto edit = [](const std::string& glb, auto&& change) {
        const std::uint32_t json_length = static_cast<unsigned char>(glb[12]) | static_cast<unsigned char>(glb[13])
                                                                                    << 8;
        json gltf = json::parse(glb.substr(20, json_length));
        change(gltf);
        std::string bin = glb.substr(20 + json_length + 8);
        bin.resize(gltf["buffers"][0]["byteLength"].get<std::size_t>());
        return make_glb(gltf, bin);
    };
    expect_error(edit(good, [](json& g) { g["accessors"][2]["count"] = 2; }), ErrorCode::ParseError,
                 "COLOR_0 (accessors[2]) has 2 elements, POSITION (accessors[0]) has 3");
    expect_error(edit(good, [](json& g) { g["accessors"][1]["count"] = 4; }), ErrorCode::ParseError,
                 "NORMAL (accessors[1]) has 4 elements");
    expect_error(edit(good, [](json& g) { g["accessors"][2]["type"] = "VEC2"; }), ErrorCode::ParseError,
                 "COLOR_0 (accessors[2]) must be VEC3 or VEC4");
    expect_error(edit(good, [](json& g) { g["accessors"][0]["count"] = 4; }), ErrorCode::ParseError, "accessors[0]");
    expect_error(edit(good, [](json& g) { g["meshes"][0]["primitives"][0]["attributes"].erase("POSITION"); }),
                 ErrorCode::ParseError, "has no POSITION");
    // float colours outside 0..1
    expect_error(edit(good,
                      [](json& g) {
                          g["accessors"][2] = accessor(0, 5126, "VEC3", 3);  // the positions: 2 > 1
                      }),
                 ErrorCode::ParseError, "outside 0..1");
    expect_error(edit(good, [](json& g) { g["extensionsRequired"] = {"EXT_unknown"}; }), ErrorCode::Unsupported,
                 "EXT_unknown");
    expect_error("glTF", ErrorCode::ParseError, "not a GLB");
}

TEST(GltfPoints, PointBudgetIsCheckedBeforeReading) {
    // 10^9 points announced by an accessor without a buffer view (it would read as zeros): refused from the count
    json gltf = {{"asset", {{"version", "2.0"}}},
                 {"accessors", {{{"componentType", 5126}, {"type", "VEC3"}, {"count", 1'000'000'000}}}},
                 {"meshes", {{{"primitives", {{{"mode", 0}, {"attributes", {{"POSITION", 0}}}}}}}}}};
    auto read = read_glb_points(make_glb(gltf, ""));
    ASSERT_FALSE(read.ok());
    EXPECT_EQ(read.error().code, ErrorCode::BudgetExceeded);
    EXPECT_NE(read.error().message.find("1000000000 points exceed the limit of 20000000"), std::string::npos)
        << read.error().message;
    // the limit applies to the total over primitives and instances, Draco ones included
    const PointCloud cloud = sample_cloud(100, false, 9);
    for (bool draco : {false, true}) {
        auto glb = write_points_glb(cloud, {.draco = draco});
        ASSERT_TRUE(glb.ok());
        PointReadOptions options;
        options.max_points = 99;
        auto over = read_glb_points(*glb, options);
        ASSERT_FALSE(over.ok());
        EXPECT_EQ(over.error().code, ErrorCode::BudgetExceeded) << over.error().message;
        options.max_points = 100;
        EXPECT_TRUE(read_glb_points(*glb, options).ok());
    }
}

TEST(GltfPoints, DracoPointCountIsCheckedBeforeDracoAllocates) {
    // a Draco kd-tree point cloud header announcing 1,694,433,304 points in a few bytes (Draco would size its
    // attributes, 20 GB, before reading a value): refused from the announced count
    std::vector<std::uint8_t> stream = {'D', 'R', 'A', 'C', 'O', 2, 3, 0, 1, 0, 0, 0x18, 0x00, 0xff, 0x64, 1, 3, 0, 9};
    draco_points::AttributeIds ids;
    ids.position = 0;
    auto decoded = draco_points::decode(stream, ids, 1'000'000);
    ASSERT_FALSE(decoded.ok());
    EXPECT_EQ(decoded.error().code, ErrorCode::BudgetExceeded);
    EXPECT_NE(decoded.error().message.find("announces 1694433304 points"), std::string::npos)
        << decoded.error().message;
    // metadata (flag 0x8000) hides the count: refused; a truncated header is a parse error
    std::vector<std::uint8_t> with_metadata = stream;
    with_metadata[10] = 0x80;
    EXPECT_EQ(draco_points::decode(with_metadata, ids, 1'000'000).error().code, ErrorCode::ParseError);
    EXPECT_EQ(draco_points::decode(std::span(stream).first(12), ids, 1'000'000).error().code, ErrorCode::ParseError);
}

TEST(GltfPoints, FormatDetection) {
    EXPECT_EQ(point_format_from_extension("scan.GLB"), PointFormat::Glb);
    EXPECT_EQ(point_format_from_extension("scan.gltf"), PointFormat::Gltf);
    EXPECT_EQ(point_format_from_media_type("model/gltf-binary"), PointFormat::Glb);
    EXPECT_EQ(point_format_from_media_type("model/gltf+json"), PointFormat::Gltf);
    EXPECT_EQ(sniff_point_format(three_points({{"mesh", 0}})), PointFormat::Glb);
    EXPECT_EQ(sniff_point_format(R"({"asset": {"version": "2.0"}})"), PointFormat::Gltf);
    EXPECT_EQ(point_media_type(PointFormat::Glb), "model/gltf-binary");
}

TEST(GltfMeshColors, ColouredMeshIsValidAndReadsBack) {
    // a grid of quads coloured by position, RGB and RGBA, plain (float COLOR_0) and Draco (normalised bytes)
    PolygonMesh grid;
    const int n = 12;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) grid.positions.push_back({i / double(n), j / double(n), 0.1 * ((i * j) % 3)});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto v = static_cast<Index>(j * (n + 1) + i);
            grid.add_face({v, v + 1, v + n + 2, v + n + 1});
        }
    std::vector<Color> colors;
    for (const Vec3& p : grid.positions)
        colors.push_back({static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z * 5), 0.5f});
    for (bool draco : {false, true})
        for (bool alpha : {false, true}) {
            SCOPED_TRACE(std::string(draco ? "draco" : "plain") + (alpha ? " rgba" : " rgb"));
            auto glb =
                write_glb(grid, {.draco = draco, .normals = true, .vertex_colors = colors, .vertex_alpha = alpha});
            ASSERT_TRUE(glb.ok()) << glb.error().message;
            const auto v = testing::run_gltf_validator(*glb);
            ASSERT_TRUE(v.ran) << v.report;
            EXPECT_EQ(v.errors, 0) << v.report;
            EXPECT_EQ(v.warnings, 0) << v.report;
            auto read = read_glb_points(*glb);
            ASSERT_TRUE(read.ok()) << read.error().message;
            ASSERT_EQ(read->size(), grid.positions.size());
            ASSERT_EQ(read->colors.size(), grid.positions.size());
            EXPECT_EQ(read->has_alpha, alpha);
            const KdTree tree(grid.positions);
            std::vector<Neighbor> nearest;
            const double tol = draco ? 0.5 / 255 + 1e-6 : 1e-7;
            for (std::size_t p = 0; p < read->size(); ++p) {
                tree.knn(read->positions[p], 1, nearest);  // Draco may reorder the vertices
                const Color& want = colors[nearest[0].index];
                EXPECT_NEAR(read->colors[p].r, want.r, tol);
                EXPECT_NEAR(read->colors[p].g, want.g, tol);
                EXPECT_NEAR(read->colors[p].b, want.b, tol);
                EXPECT_NEAR(read->colors[p].a, alpha ? 0.5 : 1.0, tol);
            }
        }
    // colours not one per vertex
    EXPECT_EQ(write_glb(grid, {.vertex_colors = std::span<const Color>(colors).first(3)}).error().code,
              ErrorCode::InvalidArgument);
}

}  // namespace
}  // namespace surfaced
