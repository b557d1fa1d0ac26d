// Geomview BEZ/BBP reader: the teapot sample, the documented header variants, errors with line numbers; and the
// tessellated teapot as a GLB that the Khronos validator accepts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include "geometry/io/bez.h"
#include "geometry/io/gltf.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced {
namespace {

TEST(Bez, EmbeddedTeapotMatchesSharedFile) {
    const std::string file = testing::read_file(std::string(SURFACED_TEST_DATA_DIR) + "/teapot/teapot32.bez");
    ASSERT_FALSE(file.empty());
    EXPECT_EQ(patch_sample_text("teapot"), file);
    EXPECT_TRUE(patch_sample_text("kettle").empty());
    ASSERT_EQ(patch_sample_names().size(), 1u);
    EXPECT_EQ(patch_sample_names()[0], "teapot");
}

TEST(Bez, ReadsTeapot) {
    auto set = read_bez(patch_sample_text("teapot"));
    ASSERT_TRUE(set.ok()) << set.error().message;
    // The data set's README: 32 bicubic patches over 290 distinct control points, rim radius 1.4, height 3.15.
    ASSERT_EQ(set->patches.size(), 32u);
    std::set<std::array<double, 3>> distinct;
    Box3 box;
    for (const BezierPatch& patch : set->patches) {
        EXPECT_EQ(patch.degree_u, 3);
        EXPECT_EQ(patch.degree_v, 3);
        ASSERT_EQ(patch.points.size(), 16u);
        for (const Vec3& p : patch.points) {
            distinct.insert({p.x + 0.0, p.y + 0.0, p.z + 0.0});
            box.add(p);
        }
    }
    EXPECT_EQ(distinct.size(), 290u);
    EXPECT_EQ(set->patches[0].points[0], (Vec3{1.4, 0, 2.4}));  // first control point in the file
    EXPECT_DOUBLE_EQ(box.max.z - box.min.z, 3.15);
}

TEST(Bez, HeaderVariants) {
    // BEZ<Nu><Nv>3: degree 2 in u, 1 in v -> 3 x 2 control points, u fastest
    auto a = read_bez("BEZ213\n0 0 0  1 0 0  2 0 0\n0 1 0  1 1 1  2 1 0\n");
    ASSERT_TRUE(a.ok()) << a.error().message;
    ASSERT_EQ(a->patches.size(), 1u);
    EXPECT_EQ(a->patches[0].degree_u, 2);
    EXPECT_EQ(a->patches[0].degree_v, 1);
    EXPECT_EQ(a->patches[0].at(1, 1), (Vec3{1, 1, 1}));

    // C prefix: 4 RGBA corner colours after the points; _ST suffix: 4 (s, t) pairs before the colours
    auto b = read_bez(
        "CBEZ113_ST\n0 0 0 1 0 0 0 1 0 1 1 0\n0 0 0 1 1 0 1 1\n"
        "1 0 0 1  0 1 0 1  0 0 1 1  1 1 1 1\n"
        "0 0 1 1 0 1 0 1 1 1 1 1\n0 0 0 1 1 0 1 1\n1 0 0 1 0 1 0 1 0 0 1 1 1 1 1 1\n");
    ASSERT_TRUE(b.ok()) << b.error().message;
    ASSERT_EQ(b->patches.size(), 2u);
    EXPECT_EQ(b->patches[1].at(1, 1), (Vec3{1, 1, 1}));

    // STBBP = BEZ333_ST; a later header switches the type of the patches after it
    std::string text = "STBBP # bicubic with texture coordinates\n";
    for (int k = 0; k < 16; ++k) text += std::to_string(k % 4) + " " + std::to_string(k / 4) + " 0\n";
    text += "0 0 0 1 1 0 1 1\nBEZ113\n0 0 5 1 0 5 0 1 5 1 1 5\n";
    auto c = read_bez(text);
    ASSERT_TRUE(c.ok()) << c.error().message;
    ASSERT_EQ(c->patches.size(), 2u);
    EXPECT_EQ(c->patches[0].degree_u, 3);
    EXPECT_EQ(c->patches[1].degree_u, 1);
    EXPECT_EQ(c->patches[1].at(1, 1), (Vec3{1, 1, 5}));

    // CRLF and comments
    auto d = read_bez("# comment\r\nBEZ113\r\n0 0 0 1 0 0 # first row\r\n0 1 0 1 1 0\r\n");
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(d->patches.size(), 1u);
}

struct BadCase {
    const char* text;
    ErrorCode code;
    std::int64_t line;
    const char* message_part;
};

TEST(Bez, ErrorsNameTheLine) {
    const BadCase cases[] = {
        {"OFF\n", ErrorCode::ParseError, 1, "expected a BEZ header"},
        {"BEZ733\n", ErrorCode::ParseError, 1, "degrees must be 1..6"},
        {"BEZ335\n", ErrorCode::ParseError, 1, "dimension must be 3 or 4"},
        {"# rational\nBEZ114\n0 0 0 1\n1 0 0 0\n", ErrorCode::InvalidArgument, 4,
         "weight (4th coordinate) must be > 0"},
        {"BEZ114\n0 0 0 1  1 0 0 1e13\n0 1 0 1  1 1 0 1\n", ErrorCode::InvalidArgument, 2, "largest weight"},
        {"BEZ113\n0 0 0\n1 0 zero\n", ErrorCode::ParseError, 3, "'zero' is not a number"},
        {"BEZ113\n0 0 0\n1 0 0\n0 1 0\n", ErrorCode::ParseError, 4, "unexpected end of file in patch 0"},
        {"BEZ113\n0 0 0\n1 0 nan\n0 1 0 1 1 0\n", ErrorCode::NonFinite, 3, "not finite"},
        {"BBP\n# nothing\n", ErrorCode::ParseError, 2, "no patches"},
        {"BBP\n0 0 0\n", ErrorCode::ParseError, 2, "unexpected end of file"},
    };
    for (const BadCase& c : cases) {
        auto result = read_bez(c.text);
        ASSERT_FALSE(result.ok()) << c.text;
        EXPECT_EQ(result.error().code, c.code) << c.text << " -> " << result.error().message;
        EXPECT_EQ(result.error().line, c.line) << c.text << " -> " << result.error().message;
        EXPECT_NE(result.error().message.find(c.message_part), std::string::npos) << result.error().message;
        EXPECT_NE(result.error().message.find("line " + std::to_string(c.line)), std::string::npos)
            << result.error().message;
    }
    EXPECT_EQ(read_bez("").error().code, ErrorCode::ParseError);
    BezReadOptions options;
    options.max_patches = 1;
    auto many = read_bez("BEZ113\n0 0 0 1 0 0 0 1 0 1 1 0\n0 0 0 1 0 0 0 1 0 1 1 0\n", options);
    ASSERT_FALSE(many.ok());
    EXPECT_EQ(many.error().code, ErrorCode::BudgetExceeded);
}

TEST(Bez, TessellatedTeapotIsValidGlb) {
    auto set = read_bez(patch_sample_text("teapot"));
    ASSERT_TRUE(set.ok());
    TessellationOptions options;
    options.tolerance = 0.01;
    auto tess = tessellate_patches(set->patches, options);
    ASSERT_TRUE(tess.ok()) << tess.error().message;
    for (bool draco : {true, false}) {
        GltfOptions gltf;
        gltf.draco = draco;
        gltf.normals = true;
        gltf.texcoords = true;
        auto glb = write_glb(tess->mesh, gltf);
        ASSERT_TRUE(glb.ok()) << glb.error().message;
        const auto report = testing::run_gltf_validator(*glb);
        ASSERT_TRUE(report.ran) << report.report;
        EXPECT_EQ(report.errors, 0) << report.report;
        EXPECT_EQ(report.warnings, 0) << report.report;
        // the JSON chunk names the attributes
        EXPECT_NE(glb->find("\"NORMAL\""), std::string::npos);
        EXPECT_NE(glb->find("\"TEXCOORD_0\""), std::string::npos);
    }
}

TEST(Bez, TextureCoordinatesBecomeTheUvs) {
    // STBBP = BEZ333_ST: after the 16 points, (s, t) at the corners (u, v) = (0, 0), (1, 0), (0, 1), (1, 1)
    std::string text = "STBBP\n";
    for (int k = 0; k < 16; ++k) text += std::to_string(k % 4) + " " + std::to_string(k / 4) + " 0\n";
    text += "0.25 0.5  0.75 0.5  0.25 1  0.75 1\n";
    text += "BEZ113\n0 0 5 1 0 5 0 1 5 1 1 5\n";  // no ST: its own (u, v)
    auto set = read_bez(text);
    ASSERT_TRUE(set.ok()) << set.error().message;
    ASSERT_EQ(set->patches.size(), 2u);
    ASSERT_TRUE(set->patches[0].corner_uvs.has_value());
    EXPECT_FALSE(set->patches[1].corner_uvs.has_value());
    EXPECT_EQ((*set->patches[0].corner_uvs)[3].x, 0.75);
    EXPECT_EQ((*set->patches[0].corner_uvs)[1].y, 0.5);

    TessellationOptions options;
    options.segments = 2;
    auto tess = tessellate_patches(set->patches, options);
    ASSERT_TRUE(tess.ok()) << tess.error().message;
    const PolygonMesh& mesh = tess->mesh;
    // patch 0 is the plane z = 0 over [0,3]^2 with x = 3u, y = 3v: every uv is (0.25 + u/2, 0.5 + v/2)
    std::size_t checked = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (std::size_t c = 0; c < 3; ++c) {
            const Vec3 p = mesh.positions[mesh.face_indices[mesh.face_offsets[f] + c]];
            const Vec2 uv = mesh.uvs[mesh.uv_indices[mesh.face_offsets[f] + c]];
            if (tess->face_patches[f] == 0) {
                EXPECT_NEAR(uv.x, 0.25 + p.x / 6, 1e-14);
                EXPECT_NEAR(uv.y, 0.5 + p.y / 6, 1e-14);
                ++checked;
            } else {
                EXPECT_NEAR(uv.x, p.x, 1e-14);  // the unit square: (u, v) = (x, y)
                EXPECT_NEAR(uv.y, p.y, 1e-14);
            }
        }
    EXPECT_EQ(checked, 3u * 8u);
    // and they reach the GLB's TEXCOORD_0 (the validator checks the accessor)
    GltfOptions gltf;
    gltf.texcoords = true;
    auto glb = write_glb(mesh, gltf);
    ASSERT_TRUE(glb.ok()) << glb.error().message;
    const auto report = testing::run_gltf_validator(*glb);
    ASSERT_TRUE(report.ran) << report.report;
    EXPECT_EQ(report.errors, 0) << report.report;
}

TEST(Bez, RationalPatchesAreHomogeneous) {
    // BEZ214: a quadratic x linear rational patch, points (x, y, z, w) already multiplied by w (geomview's HPoint3):
    // the quarter circle (1,0) (1,1) (0,1) with weights 1, sqrt(2)/2, 1, extruded along z -- a quarter cylinder.
    const double s = std::sqrt(0.5);
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "BEZ214\n1 0 0 1  %.17g %.17g 0 %.17g  0 1 0 1\n1 0 2 1  %.17g %.17g %.17g %.17g  0 1 2 1\n", s, s, s,
                  s, s, 2 * s, s);
    auto set = read_bez(buf);
    ASSERT_TRUE(set.ok()) << set.error().message;
    ASSERT_EQ(set->patches.size(), 1u);
    const BezierPatch& patch = set->patches[0];
    ASSERT_TRUE(patch.rational());
    EXPECT_EQ(patch.weights[1], s);
    EXPECT_NEAR(patch.at(1, 1).x, 1.0, 1e-15);  // (s, s, 2s) / s
    EXPECT_NEAR(patch.at(1, 1).z, 2.0, 1e-15);
    for (int a = 0; a <= 20; ++a)
        for (int b = 0; b <= 4; ++b) {
            const Vec3 p = evaluate(patch, a / 20.0, b / 4.0);
            EXPECT_NEAR(std::hypot(p.x, p.y), 1.0, 1e-12);
            EXPECT_NEAR(p.z, b / 2.0, 1e-12);
        }
    TessellationOptions options;
    options.tolerance = 1e-3;
    auto tess = tessellate_patches(set->patches, options);
    ASSERT_TRUE(tess.ok()) << tess.error().message;
    EXPECT_LE(tess->plan.error_bound, 1e-3);
    // the chord of a unit circle arc of angle a deviates by 1 - cos(a/2): the segments needed are at least
    // (pi/2) / (2 acos(1 - 1e-3)) = 17.6, and a guarantee cannot use fewer
    EXPECT_GE(tess->plan.segments[0].nu, 18);
}

}  // namespace
}  // namespace surfaced
