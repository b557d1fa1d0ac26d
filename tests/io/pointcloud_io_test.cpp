// Point-cloud files: PLY / OBJ / XYZ readers on good and malformed input (with the line or offset they name), PLY
// round trips, format detection, and GLB POINTS output checked by the Khronos validator and, for Draco, decoded
// with Draco's own decoder.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <draco/compression/decode.h>
#include <draco/point_cloud/point_cloud.h>
#include <nlohmann/json.hpp>

#include "geometry/io/pointcloud_glb.h"
#include "geometry/io/pointcloud_io.h"
#include "geometry/pointcloud/kd_tree.h"
#include "tests/support/gltf_validator.h"

namespace surfaced {
namespace {

using nlohmann::json;

PointCloud colored_cloud(std::size_t n, bool alpha, std::uint64_t seed = 1) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-3, 3);
    std::uniform_int_distribution<int> byte(0, 255);
    PointCloud cloud;
    cloud.has_alpha = alpha;
    for (std::size_t i = 0; i < n; ++i) {
        cloud.positions.push_back({u(rng), u(rng), u(rng) * 0.1});
        Vec3 nrm{u(rng), u(rng), u(rng) + 0.01};
        cloud.normals.push_back(nrm * (1.0 / norm(nrm)));
        cloud.colors.push_back(
            {byte(rng) / 255.0f, byte(rng) / 255.0f, byte(rng) / 255.0f, alpha ? byte(rng) / 255.0f : 1.0f});
    }
    return cloud;
}

void expect_same_cloud(const PointCloud& a, const PointCloud& b) {
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(a.positions, b.positions);
    ASSERT_EQ(a.normals.size(), b.normals.size());
    for (std::size_t i = 0; i < a.normals.size(); ++i) EXPECT_LT(norm(a.normals[i] - b.normals[i]), 1e-15);
    ASSERT_EQ(a.colors.size(), b.colors.size());
    EXPECT_EQ(a.has_alpha, b.has_alpha);
    for (std::size_t i = 0; i < a.colors.size(); ++i) {
        EXPECT_NEAR(a.colors[i].r, b.colors[i].r, 1e-6);
        EXPECT_NEAR(a.colors[i].g, b.colors[i].g, 1e-6);
        EXPECT_NEAR(a.colors[i].b, b.colors[i].b, 1e-6);
        EXPECT_NEAR(a.colors[i].a, b.colors[i].a, 1e-6);
    }
}

// ---- PLY ---------------------------------------------------------------------------------------------------------

TEST(PointPly, RoundTripsBinaryAndAscii) {
    for (bool alpha : {false, true}) {
        const PointCloud cloud = colored_cloud(500, alpha);
        for (PlyEncoding encoding : {PlyEncoding::BinaryLittleEndian, PlyEncoding::Ascii}) {
            const std::string bytes = write_ply_points(cloud, encoding);
            auto read = read_ply_points(bytes);
            ASSERT_TRUE(read.ok()) << read.error().message;
            expect_same_cloud(cloud, read.value());
        }
    }
    PointCloud bare;
    bare.positions = {{1, 2, 3}, {0.1, 0.2, 0.3}};
    auto read = read_ply_points(write_ply_points(bare, PlyEncoding::Ascii));
    ASSERT_TRUE(read.ok());
    expect_same_cloud(bare, read.value());
}

TEST(PointPly, ReadsBigEndianFloatColoursAndSkipsOtherElements) {
    // a "camera" element before the vertices, float colours, extra properties and faces after them
    std::string ply =
        "ply\nformat binary_big_endian 1.0\nelement camera 1\nproperty list uchar float params\n"
        "element vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty short quality\n"
        "property float red\nproperty float green\nproperty float blue\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    auto be32 = [&](std::uint32_t v) {
        for (int i = 3; i >= 0; --i) ply += static_cast<char>((v >> (8 * i)) & 0xff);
    };
    auto f32 = [&](float v) { be32(std::bit_cast<std::uint32_t>(v)); };
    ply += static_cast<char>(2);  // camera params: 2 floats
    f32(1.5f);
    f32(2.5f);
    const float vertices[2][6] = {{1, 2, 3, 0.25f, 0.5f, 1}, {-1, -2, -3, 0, 0.125f, 0.75f}};
    for (const auto& v : vertices) {
        f32(v[0]);
        f32(v[1]);
        f32(v[2]);
        ply += std::string("\x00\x07", 2);  // quality
        f32(v[3]);
        f32(v[4]);
        f32(v[5]);
    }
    ply += static_cast<char>(3);
    be32(0);
    be32(1);
    be32(1);
    auto read = read_ply_points(ply);
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->size(), 2u);
    EXPECT_EQ(read->positions[1], (Vec3{-1, -2, -3}));
    ASSERT_EQ(read->colors.size(), 2u);
    EXPECT_FLOAT_EQ(read->colors[0].g, 0.5f);
    EXPECT_FLOAT_EQ(read->colors[1].b, 0.75f);
    EXPECT_FALSE(read->has_normals());
    EXPECT_FALSE(read->has_alpha);
    EXPECT_EQ(read->confidence, (std::vector<float>{7, 7}));  // `quality` is read as the confidence
}

// Per-point confidence: `confidence` (preferred) or `quality`, any numeric type, not scaled; written as float and
// read back; negative or non-finite values are refused with the line.
TEST(PointPly, Confidence) {
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar quality\nproperty float confidence\nend_header\n"
        "0 0 0 200 0.5\n1 0 0 100 1\n0 1 0 0 0\n";
    auto read = read_ply_points(ply);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read->confidence, (std::vector<float>{0.5f, 1.0f, 0.0f}));
    EXPECT_TRUE(validate(*read).ok());

    PointCloud cloud = colored_cloud(50, false);
    for (std::size_t i = 0; i < cloud.size(); ++i) cloud.confidence.push_back(0.1f * static_cast<float>(i) + 1e-3f);
    for (PlyEncoding encoding : {PlyEncoding::BinaryLittleEndian, PlyEncoding::Ascii}) {
        auto back = read_ply_points(write_ply_points(cloud, encoding));
        ASSERT_TRUE(back.ok()) << back.error().message;
        expect_same_cloud(cloud, *back);
        EXPECT_EQ(back->confidence, cloud.confidence);  // float, exact in both encodings
    }

    const std::string negative =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
        "property float confidence\nend_header\n0 0 0 1\n1 0 0 -0.5\n";
    auto bad = read_ply_points(negative);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().code, ErrorCode::ParseError);
    EXPECT_EQ(bad.error().line, 10);

    PointCloud invalid = cloud;
    invalid.confidence[3] = std::nanf("");
    const Status status = validate(invalid);
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().element, 3);
    invalid.confidence.pop_back();
    EXPECT_FALSE(validate(invalid).ok());  // wrong size
}

TEST(PointPly, AsciiUcharColoursAndNormals) {
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
        "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\n"
        "property uchar blue\nproperty uchar alpha\nend_header\n"
        "0 0 0 0 0 2 255 0 0 255\n1 0 0 0 0 1 0 255 0 128\n0 1 0 0 0 1 0 0 51 0\n";
    auto read = read_ply_points(ply);
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->size(), 3u);
    EXPECT_EQ(read->normals[0], (Vec3{0, 0, 1}));  // normalised
    EXPECT_TRUE(read->has_alpha);
    EXPECT_FLOAT_EQ(read->colors[0].r, 1.0f);
    EXPECT_FLOAT_EQ(read->colors[1].a, 128.0f / 255.0f);
    EXPECT_FLOAT_EQ(read->colors[2].b, 0.2f);
}

struct Malformed {
    const char* name;
    std::string bytes;
    ErrorCode code;
    std::int64_t line;    // -1: not checked
    std::int64_t offset;  // -1: not checked
};

TEST(PointPly, MalformedInputNamesTheLineOrOffset) {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    const std::string bin_head =
        "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float "
        "z\nend_header\n";
    const std::string list_head =
        "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
        "property list uchar float extra\nend_header\n";
    const std::vector<Malformed> cases = {
        {"bad number", head + "0 0 0\n1 x 0\n", ErrorCode::ParseError, 9, -1},
        // too few bytes for the declared count: caught by the header check, naming the element line
        {"short ascii", head + "0 0 0\n1 1\n", ErrorCode::ParseError, 3, -1},
        {"truncated ascii", head + "0 0 0\n1 1                 \n", ErrorCode::ParseError, 9, -1},
        {"nan", head + "0 0 0\nnan 0 0\n", ErrorCode::NonFinite, 9, -1},
        {"no z", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
         ErrorCode::ParseError, 3, -1},
        {"no vertex element", "ply\nformat ascii 1.0\nelement face 0\nend_header\n", ErrorCode::ParseError, -1, -1},
        {"empty vertex element",
         "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
         ErrorCode::ParseError, 3, -1},
        // a header count the bytes cannot hold fails before anything is reserved
        {"absurd count",
         "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
         "property float y\nproperty float z\nend_header\n" +
             std::string(24, '\0'),
         ErrorCode::ParseError, 3, -1},
        {"short binary", bin_head + std::string(20, '\0'), ErrorCode::ParseError, 3, -1},
        // enough bytes for the minimum, but the second vertex's list claims 200 floats
        {"truncated binary", list_head + std::string(12, '\0') + '\0' + std::string(12, '\0') + '\xc8' + "abc",
         ErrorCode::ParseError, -1, static_cast<std::int64_t>(list_head.size() + 26)},
        {"colour out of range",
         "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
         "property float z\nproperty float red\nproperty float green\nproperty float blue\n"
         "end_header\n0 0 0 0.5 2 0\n",
         ErrorCode::ParseError, 11, -1},
        {"not ply", "hello\n", ErrorCode::ParseError, 1, -1},
    };
    for (const Malformed& c : cases) {
        auto read = read_ply_points(c.bytes);
        ASSERT_FALSE(read.ok()) << c.name;
        EXPECT_EQ(read.error().code, c.code) << c.name << ": " << read.error().message;
        if (c.line >= 0) {
            EXPECT_EQ(read.error().line, c.line) << c.name << ": " << read.error().message;
        }
        if (c.offset >= 0) {
            EXPECT_EQ(read.error().offset, c.offset) << c.name << ": " << read.error().message;
        }
        EXPECT_FALSE(read.error().message.empty());
    }
}

TEST(PointPly, PointBudgetIsCheckedFromTheHeader) {
    const PointCloud cloud = colored_cloud(100, false);
    const std::string bytes = write_ply_points(cloud);
    auto read = read_ply_points(bytes, {.max_points = 99});
    ASSERT_FALSE(read.ok());
    EXPECT_EQ(read.error().code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(read.error().line, 4);  // the "element vertex 100" line
    EXPECT_TRUE(read_ply_points(bytes, {.max_points = 100}).ok());
}

// ---- OBJ ---------------------------------------------------------------------------------------------------------

TEST(PointObj, VerticesColoursAndMatchingNormals) {
    const std::string obj =
        "# points\nv 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 0.5\nvn 0 0 2\nvn 0 0 1\nvn 0 1 0\nf 1 2 3\n"
        "usemtl x\n";
    auto read = read_obj_points(obj);
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->size(), 3u);
    ASSERT_EQ(read->normals.size(), 3u);
    EXPECT_EQ(read->normals[0], (Vec3{0, 0, 1}));
    ASSERT_EQ(read->colors.size(), 3u);
    EXPECT_FLOAT_EQ(read->colors[2].b, 0.5f);

    // 0..255 colours are scaled; a count mismatch drops the normals; a v without colour drops the colours
    auto scaled = read_obj_points("v 0 0 0 255 0 51\nv 1 1 1 0 0 0\nvn 0 0 1\n");
    ASSERT_TRUE(scaled.ok());
    EXPECT_FALSE(scaled->has_normals());
    EXPECT_FLOAT_EQ(scaled->colors[0].b, 0.2f);
    auto mixed = read_obj_points("v 0 0 0 1 0 0\nv 1 1 1\n");
    ASSERT_TRUE(mixed.ok());
    EXPECT_FALSE(mixed->has_colors());
    auto with_w = read_obj_points("v 0 0 0 1\n");
    ASSERT_TRUE(with_w.ok());
    EXPECT_EQ(with_w->size(), 1u);
}

TEST(PointObj, MalformedInputNamesTheLine) {
    const std::vector<Malformed> cases = {
        {"bad number", "v 0 0 0\n\nv 1 y 0\n", ErrorCode::ParseError, 3, -1},
        {"two values", "# c\nv 1 2\n", ErrorCode::ParseError, 2, -1},
        {"five values", "v 1 2 3 4 5\n", ErrorCode::ParseError, 1, -1},
        {"inf", "v 0 0 0\nv 1e999 0 0\n", ErrorCode::NonFinite, 2, -1},
        {"negative colour", "v 0 0 0 -1 0 0\n", ErrorCode::ParseError, 1, -1},
        {"bad normal", "v 0 0 0\nvn 0 1\n", ErrorCode::ParseError, 2, -1},
        {"no points", "f 1 2 3\n", ErrorCode::ParseError, -1, -1},
        {"utf16 without a byte order mark", std::string("v\x00 \x00", 4), ErrorCode::ParseError, 1, 1},
        {"utf16 cut short", std::string("\xff\xfev\x00 ", 5), ErrorCode::ParseError, -1, 4},
    };
    for (const Malformed& c : cases) {
        auto read = read_obj_points(c.bytes);
        ASSERT_FALSE(read.ok()) << c.name;
        EXPECT_EQ(read.error().code, c.code) << c.name << ": " << read.error().message;
        if (c.line >= 0) {
            EXPECT_EQ(read.error().line, c.line) << c.name << ": " << read.error().message;
        }
        if (c.offset >= 0) {
            EXPECT_EQ(read.error().offset, c.offset) << c.name;
        }
    }
    auto budget = read_obj_points("v 0 0 0\nv 1 1 1\nv 2 2 2\n", {.max_points = 2});
    ASSERT_FALSE(budget.ok());
    EXPECT_EQ(budget.error().code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(budget.error().line, 3);
}

TEST(PointObj, Utf16WithByteOrderMarkReadsLikeUtf8) {
    const std::string text = "# scan\nv 1 2 3\nv 4 5 6\n";
    std::string le = "\xff\xfe", be = "\xfe\xff";
    for (char c : text) {
        le += {c, '\0'};
        be += {'\0', c};
    }
    auto utf8 = read_obj_points(text);
    ASSERT_TRUE(utf8.ok()) << utf8.error().message;
    for (const std::string& bytes : {le, be}) {
        auto utf16 = read_obj_points(bytes);
        ASSERT_TRUE(utf16.ok()) << utf16.error().message;
        EXPECT_EQ(utf16->positions, utf8->positions);
    }
    auto xyz = read_xyz_points(le.substr(0, 2 + 2 * 7) + std::string("1\0 \0002\0 \0003\0\n\0", 12));
    ASSERT_TRUE(xyz.ok()) << xyz.error().message;
    ASSERT_EQ(xyz->size(), 1u);
    EXPECT_EQ(xyz->positions[0], (Vec3{1, 2, 3}));
}

// ---- XYZ ---------------------------------------------------------------------------------------------------------

TEST(PointXyz, ThreeSixAndNineColumns) {
    auto plain = read_xyz_points("# scan\n1 2 3\n4,5,6\n\n 7\t8 9 # last\n");
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    ASSERT_EQ(plain->size(), 3u);
    EXPECT_EQ(plain->positions[1], (Vec3{4, 5, 6}));
    EXPECT_FALSE(plain->has_normals());
    auto normals = read_xyz_points("0 0 0 0 0 3\r\n1 1 1 0 2 0\r\n");
    ASSERT_TRUE(normals.ok());
    EXPECT_EQ(normals->normals[0], (Vec3{0, 0, 1}));
    auto colored = read_xyz_points("0 0 0 0 0 1 255 128 0\n1 1 1 0 0 1 0 0 255\n");
    ASSERT_TRUE(colored.ok());
    EXPECT_FLOAT_EQ(colored->colors[0].g, 128.0f / 255.0f);
    EXPECT_FLOAT_EQ(colored->colors[1].b, 1.0f);
}

TEST(PointXyz, MalformedInputNamesTheLine) {
    const std::vector<Malformed> cases = {
        {"column change", "0 0 0\n1 1 1\n# c\n2 2 2 0 0 1\n", ErrorCode::ParseError, 4, -1},
        {"four columns", "\n0 0 0 1\n", ErrorCode::ParseError, 2, -1},
        {"not a number", "0 0 0\n1 one 1\n", ErrorCode::ParseError, 2, -1},
        {"nan", "0 0 0\nnan 1 1\n", ErrorCode::NonFinite, 2, -1},
        {"too many", "1 2 3 4 5 6 7 8 9 10\n", ErrorCode::ParseError, 1, -1},
        {"comments only", "# nothing\n\n", ErrorCode::ParseError, -1, -1},
        {"empty", "", ErrorCode::ParseError, -1, -1},
        {"nul", std::string("0 0 0\n1 1\0 1\n", 12), ErrorCode::ParseError, 2, -1},
    };
    for (const Malformed& c : cases) {
        auto read = read_xyz_points(c.bytes);
        ASSERT_FALSE(read.ok()) << c.name;
        EXPECT_EQ(read.error().code, c.code) << c.name << ": " << read.error().message;
        if (c.line >= 0) {
            EXPECT_EQ(read.error().line, c.line) << c.name << ": " << read.error().message;
        }
    }
}

TEST(PointFormats, DetectionByNameMediaTypeAndContent) {
    EXPECT_EQ(point_format_from_extension("scan.XYZ"), PointFormat::Xyz);
    EXPECT_EQ(point_format_from_extension("a/b.ply"), PointFormat::Ply);
    EXPECT_EQ(point_format_from_extension("b.obj"), PointFormat::Obj);
    EXPECT_EQ(point_format_from_extension("b.stl"), std::nullopt);
    EXPECT_EQ(point_format_from_media_type("application/ply"), PointFormat::Ply);
    EXPECT_EQ(point_format_from_media_type("model/obj; charset=utf-8"), PointFormat::Obj);
    EXPECT_EQ(point_format_from_media_type("text/x-xyz"), PointFormat::Xyz);
    EXPECT_EQ(point_format_from_media_type("model/stl"), std::nullopt);
    EXPECT_EQ(sniff_point_format("ply\nformat ascii 1.0\n"), PointFormat::Ply);
    EXPECT_EQ(sniff_point_format("# c\nv 1 2 3\n"), PointFormat::Obj);
    EXPECT_EQ(sniff_point_format("# c\n1.5, 2, 3\n"), PointFormat::Xyz);
    EXPECT_EQ(sniff_point_format("solid x\n"), std::nullopt);
}

// ---- GLB ---------------------------------------------------------------------------------------------------------

struct Glb {
    json gltf;
    std::string bin;
};

Glb split(std::string_view glb) {
    Glb out;
    auto u32 = [&](std::size_t at) {
        std::uint32_t v = 0;
        std::memcpy(&v, glb.data() + at, 4);
        return v;
    };
    EXPECT_GE(glb.size(), 28u);
    EXPECT_EQ(glb.substr(0, 4), "glTF");
    EXPECT_EQ(u32(8), glb.size());
    const std::uint32_t json_length = u32(12);
    out.gltf = json::parse(glb.substr(20, json_length));
    const std::size_t bin_at = 20 + json_length;
    if (bin_at + 8 <= glb.size()) out.bin = std::string(glb.substr(bin_at + 8, u32(bin_at)));
    return out;
}

void expect_valid(const std::string& glb) {
    const auto v = testing::run_gltf_validator(glb);
    ASSERT_TRUE(v.ran) << v.report;
    EXPECT_EQ(v.errors, 0) << v.report;
    EXPECT_EQ(v.warnings, 0) << v.report;
}

TEST(PointGlb, PlainPointsAreValidAndExact) {
    for (bool alpha : {false, true}) {
        const PointCloud cloud = colored_cloud(300, alpha);
        auto glb = write_points_glb(cloud, {.draco = false});
        ASSERT_TRUE(glb.ok()) << glb.error().message;
        expect_valid(glb.value());
        const Glb parts = split(glb.value());
        const json& prim = parts.gltf["meshes"][0]["primitives"][0];
        EXPECT_EQ(prim["mode"], 0);
        EXPECT_FALSE(prim.contains("indices"));
        ASSERT_TRUE(prim["attributes"].contains("NORMAL"));
        const json& color = parts.gltf["accessors"][prim["attributes"]["COLOR_0"].get<int>()];
        EXPECT_EQ(color["type"], alpha ? "VEC4" : "VEC3");
        const json& position = parts.gltf["accessors"][prim["attributes"]["POSITION"].get<int>()];
        EXPECT_EQ(position["count"], 300);
        const json& view = parts.gltf["bufferViews"][position["bufferView"].get<int>()];
        const std::size_t offset = view.value("byteOffset", 0);
        for (std::size_t i = 0; i < cloud.size(); ++i) {
            float xyz[3];
            std::memcpy(xyz, parts.bin.data() + offset + 12 * i, 12);
            for (int k = 0; k < 3; ++k) EXPECT_EQ(xyz[k], static_cast<float>(cloud.positions[i][k]));
        }
    }
    PointCloud bare;
    bare.positions = {{0, 0, 0}};
    auto glb = write_points_glb(bare, {.draco = false});
    ASSERT_TRUE(glb.ok());
    expect_valid(glb.value());
}

TEST(PointGlb, DracoPointsAreValidAndDecodeBack) {
    const int bits = 14;
    for (bool alpha : {false, true}) {
        const PointCloud cloud = colored_cloud(2000, alpha, 5);
        auto glb = write_points_glb(cloud, {.draco = true, .quantize_position = bits});
        ASSERT_TRUE(glb.ok()) << glb.error().message;
        expect_valid(glb.value());
        const Glb parts = split(glb.value());
        EXPECT_EQ(parts.gltf["extensionsRequired"], json::array({"KHR_draco_mesh_compression"}));
        const json& prim = parts.gltf["meshes"][0]["primitives"][0];
        EXPECT_EQ(prim["mode"], 0);
        const json& ext = prim["extensions"]["KHR_draco_mesh_compression"];
        const json& view = parts.gltf["bufferViews"][ext["bufferView"].get<int>()];
        draco::DecoderBuffer buffer;
        buffer.Init(parts.bin.data() + view.value("byteOffset", 0), view["byteLength"].get<std::size_t>());
        draco::Decoder decoder;
        auto decoded = decoder.DecodePointCloudFromBuffer(&buffer);
        ASSERT_TRUE(decoded.ok()) << decoded.status().error_msg();
        const std::unique_ptr<draco::PointCloud> pc = std::move(decoded).value();
        ASSERT_EQ(pc->num_points(), cloud.size());
        auto attribute = [&](const char* name) {
            return pc->GetAttributeByUniqueId(ext["attributes"][name].get<std::uint32_t>());
        };
        const draco::PointAttribute* pos = attribute("POSITION");
        const draco::PointAttribute* nrm = attribute("NORMAL");
        const draco::PointAttribute* col = attribute("COLOR_0");
        ASSERT_TRUE(pos && nrm && col);
        ASSERT_EQ(col->num_components(), alpha ? 4 : 3);
        // Draco may reorder points: match each decoded point to the nearest original. Quantization puts every
        // coordinate within half a step of the largest extent over 2^bits - 1 steps.
        const Box3 box = cloud.bounds();
        double extent = 0;
        for (int k = 0; k < 3; ++k) extent = std::max(extent, box.max[k] - box.min[k]);
        const double step = extent / ((1 << bits) - 1);
        const KdTree tree(cloud.positions);
        std::vector<Neighbor> nearest;
        std::vector<char> used(cloud.size(), 0);
        for (draco::PointIndex p(0); p < pc->num_points(); ++p) {
            float xyz[3], n[3];
            std::uint8_t rgba[4] = {0, 0, 0, 255};
            ASSERT_TRUE(pos->ConvertValue<float>(pos->mapped_index(p), 3, xyz));
            ASSERT_TRUE(nrm->ConvertValue<float>(nrm->mapped_index(p), 3, n));
            ASSERT_TRUE(
                col->ConvertValue<std::uint8_t>(col->mapped_index(p), static_cast<std::int8_t>(alpha ? 4 : 3), rgba));
            const Vec3 q{xyz[0], xyz[1], xyz[2]};
            tree.knn(q, 1, nearest);
            const std::size_t i = nearest[0].index;
            EXPECT_FALSE(used[i]) << "two decoded points match original " << i;
            used[i] = 1;
            for (int k = 0; k < 3; ++k) EXPECT_LE(std::fabs(q[k] - cloud.positions[i][k]), 0.5 * step + 1e-6);
            const Vec3 decoded_normal{n[0], n[1], n[2]};
            EXPECT_GT(dot(decoded_normal, cloud.normals[i]) / norm(decoded_normal), std::cos(0.01));
            const Color& c = cloud.colors[i];
            EXPECT_EQ(rgba[0], std::lround(c.r * 255));
            EXPECT_EQ(rgba[1], std::lround(c.g * 255));
            EXPECT_EQ(rgba[2], std::lround(c.b * 255));
            if (alpha) {
                EXPECT_EQ(rgba[3], std::lround(c.a * 255));
            }
        }
    }
}

TEST(PointGlb, RejectsEmptyAndInvalidClouds) {
    EXPECT_EQ(write_points_glb(PointCloud{}).error().code, ErrorCode::InvalidArgument);
    PointCloud bad;
    bad.positions = {{0, 0, 0}, {1, 1, 1}};
    bad.normals = {{0, 0, 1}};
    EXPECT_EQ(write_points_glb(bad).error().code, ErrorCode::InvalidArgument);
    PointCloud ok;
    ok.positions = {{0, 0, 0}};
    EXPECT_EQ(write_points_glb(ok, {.quantize_position = 30}).error().code, ErrorCode::InvalidArgument);
}

}  // namespace
}  // namespace surfaced
