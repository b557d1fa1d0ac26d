// OBJ free-form Bézier and B-spline surfaces (geometry/io/obj_patches.h): the teapot written as `cstype bezier`
// surfaces tessellates exactly as its BEZ form; multi-segment surfaces split into patches sharing their boundary
// control points; rational surfaces take the vertices' w; `cstype [rat] bspline` surfaces (the NURBS sphere, torus,
// random surfaces) read as their Bézier decomposition; everything refused names its line.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <string>

#include "geometry/io/bez.h"
#include "geometry/io/obj_patches.h"
#include "geometry/surfaces/bspline_surface.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/nurbs_surfaces.h"

namespace surfaced {
namespace {

std::string number(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

//! The patch set as OBJ free-form surfaces: distinct control points as `v` lines, one surf per patch.
std::string as_obj(const PatchSet& set) {
    std::map<std::array<double, 3>, std::size_t> index;
    std::string vertices, surfaces;
    for (const BezierPatch& patch : set.patches) {
        surfaces += "deg " + std::to_string(patch.degree_u) + " " + std::to_string(patch.degree_v) + "\n";
        surfaces += "surf 0 1 0 1";
        for (const Vec3& p : patch.points) {
            auto [it, inserted] = index.emplace(std::array<double, 3>{p.x, p.y, p.z}, index.size() + 1);
            if (inserted) vertices += "v " + number(p.x) + " " + number(p.y) + " " + number(p.z) + "\n";
            surfaces += " " + std::to_string(it->second);
        }
        surfaces += "\nparm u 0 1\nparm v 0 1\nend\n";
    }
    return "# the Utah teapot as free-form Bezier surfaces\ng teapot\n" + vertices + "cstype bezier\n" + surfaces;
}

PatchSet teapot() {
    auto set = read_bez(patch_sample_text("teapot"));
    EXPECT_TRUE(set.ok());
    return set.ok() ? set.value() : PatchSet{};
}

TEST(ObjPatches, TeapotTessellatesAsItsBezForm) {
    const PatchSet bez = teapot();
    const std::string obj = as_obj(bez);
    auto read = read_obj_patches(obj);
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->patches.size(), 32u);
    for (std::size_t p = 0; p < 32; ++p) EXPECT_EQ(read->patches[p].points, bez.patches[p].points) << "patch " << p;
    for (double tolerance : {0.01, 0.003}) {
        TessellationOptions options;
        options.tolerance = tolerance;
        auto a = tessellate_patches(bez.patches, options);
        auto b = tessellate_patches(read->patches, options);
        ASSERT_TRUE(a.ok() && b.ok());
        EXPECT_EQ(a->mesh.positions, b->mesh.positions);
        EXPECT_EQ(a->mesh.face_indices, b->mesh.face_indices);
        EXPECT_EQ(a->mesh.face_offsets, b->mesh.face_offsets);
        EXPECT_EQ(a->plan.error_bound, b->plan.error_bound);
    }
}

TEST(ObjPatches, MultiSegmentSurfaceSplitsIntoPatches) {
    // degree 3 x 2 over 2 x 1 segments: a (2*3+1) x (1*2+1) = 7 x 3 net, u fastest; negative references
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> coord(-1, 1);
    std::vector<Vec3> net;
    std::string text = "cstype bezier\ndeg 3 2\n";
    for (int k = 0; k < 21; ++k) {
        net.push_back({coord(rng), coord(rng), coord(rng)});
        text += "v " + number(net.back().x) + " " + number(net.back().y) + " " + number(net.back().z) + "\n";
    }
    text += "surf 0 2 0 1";
    for (int k = 0; k < 21; ++k) text += " " + std::to_string(k - 21) + "/1/1";  // v/vt/vn forms, relative
    text += "\nparm u 0 1 2\nparm v 0 1\nend\n";
    auto read = read_obj_patches(text);
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->patches.size(), 2u);
    for (int s = 0; s < 2; ++s) {
        const BezierPatch& patch = read->patches[static_cast<std::size_t>(s)];
        EXPECT_EQ(patch.degree_u, 3);
        EXPECT_EQ(patch.degree_v, 2);
        EXPECT_FALSE(patch.rational());
        for (int j = 0; j <= 2; ++j)
            for (int i = 0; i <= 3; ++i) EXPECT_EQ(patch.at(i, j), net[static_cast<std::size_t>(j * 7 + s * 3 + i)]);
    }
    // the blocks share their boundary column: the tessellation is one welded strip with no crack between them
    TessellationOptions options;
    options.segments = 5;
    auto tess = tessellate_patches(read->patches, options);
    ASSERT_TRUE(tess.ok());
    EXPECT_EQ(tess->mesh.vertex_count(), 11u * 6u);
    EXPECT_EQ(testing::boundary_loop_count(tess->mesh), 1u);
}

TEST(ObjPatches, RationalSurfacesUseTheWeights) {
    // a quarter cylinder: the quarter circle with weights 1, sqrt(2)/2, 1 (Euclidean points), extruded along z
    const std::string w = number(std::sqrt(0.5));
    const std::string text = "v 1 0 0\nv 1 1 0 " + w + "\nv 0 1 0\nv 1 0 1\nv 1 1 1 " + w +
                             "\nv 0 1 1\ncstype rat bezier\ndeg 2 1\nsurf 0 1 0 1 1 2 3 4 5 6\nend\n";
    auto read = read_obj_patches(text);
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->patches.size(), 1u);
    ASSERT_TRUE(read->patches[0].rational());
    for (int a = 0; a <= 16; ++a) {
        const Vec3 p = evaluate(read->patches[0], a / 16.0, 0.5);
        EXPECT_NEAR(std::hypot(p.x, p.y), 1.0, 1e-12);
    }
    // without `rat` the same vertices make a polynomial patch (w ignored, as the specification says)
    std::string polynomial = text;
    polynomial.replace(polynomial.find("rat "), 4, "");
    auto plain = read_obj_patches(polynomial);
    ASSERT_TRUE(plain.ok());
    EXPECT_FALSE(plain->patches[0].rational());
}

struct BadCase {
    std::string text;
    ErrorCode code;
    std::int64_t line;
    const char* message;
};

TEST(ObjPatches, ErrorsNameTheLine) {
    const std::string header = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";  // lines 1-4
    const std::string quad = "surf 0 1 0 1 1 2 3 4\n";
    std::string lines11 = header;
    for (int k = 5; k <= 11; ++k) lines11 += "# line " + std::to_string(k) + "\n";
    const BadCase cases[] = {
        {lines11 + "cstype cardinal\ndeg 1 1\n" + quad + "end\n", ErrorCode::Unsupported, 12,
         "line 12: cstype cardinal is not supported"},
        {header + "cstype rat taylor\n", ErrorCode::Unsupported, 5, "cstype rat taylor is not supported"},
        {header + "cstype nurbs\n", ErrorCode::ParseError, 5, "unknown cstype"},
        {header + "cstype bezier\ndeg 1 1\n" + quad + "trim 0 1 1\nend\n", ErrorCode::Unsupported, 8, "trimming"},
        {header + "cstype bezier\ndeg 2 1\n" + quad + "end\n", ErrorCode::ParseError, 7, "needs (1*2+1) x (1*1+1) = 6"},
        {header + "cstype bezier\ndeg 1 1\nsurf 0 1 0 1 1 2 3 9\nend\n", ErrorCode::ParseError, 7,
         "refers to vertex 9, but 4 vertices"},
        {header + "cstype bezier\ndeg 1 1\nsurf 0 1 0 1 1 2 3 x\nend\n", ErrorCode::ParseError, 7,
         "not a vertex index"},
        {header + "cstype bezier\ndeg 1 1\n" + quad, ErrorCode::ParseError, 7, "surf has no matching end"},
        {header + "deg 1 1\n" + quad + "end\n", ErrorCode::ParseError, 6, "surf before any cstype"},
        {header + "cstype bezier\ndeg 1\n" + quad + "end\n", ErrorCode::ParseError, 7, "two degrees"},
        {header + "cstype bezier\ndeg 1 16\n", ErrorCode::InvalidArgument, 6, "outside 1..15"},
        {header + "cstype bezier\ndeg 1 1\n" + quad + "parm u 0 0.5\nend\n", ErrorCode::Unsupported, 7,
         "sub-ranges are not supported"},
        {header + "cstype bezier\ndeg 1 1\n" + quad + "parm u 1 0\nend\n", ErrorCode::ParseError, 8, "must increase"},
        {header + "parm u 0 1\n", ErrorCode::ParseError, 5, "parm outside a surf"},
        {header + "end\n", ErrorCode::ParseError, 5, "end without a surf"},
        {"v 0 0 nan\n", ErrorCode::NonFinite, 1, "not finite"},
        {"v 0 0\n", ErrorCode::ParseError, 1, "missing v z"},
        {header + "f 1 2 3\n", ErrorCode::ParseError, 5, "no free-form surfaces"},
        {"v 1 0 0 0\nv 0 0 0\nv 0 1 0\nv 1 1 0\ncstype rat bezier\ndeg 1 1\n" + quad + "end\n",
         ErrorCode::InvalidArgument, 7, "weight 0 must be a finite number > 0"},
    };
    for (const BadCase& c : cases) {
        auto result = read_obj_patches(c.text);
        ASSERT_FALSE(result.ok()) << c.text;
        EXPECT_EQ(result.error().code, c.code) << c.text << " -> " << result.error().message;
        EXPECT_EQ(result.error().line, c.line) << c.text << " -> " << result.error().message;
        EXPECT_NE(result.error().message.find(c.message), std::string::npos) << result.error().message;
        EXPECT_NE(result.error().message.find("line " + std::to_string(c.line) + ": "), std::string::npos)
            << result.error().message;
    }
}

TEST(ObjPatches, BudgetsBeforeAllocation) {
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 0 0\nv 2 1 0\ncstype bezier\ndeg 1 1\n"
        "surf 0 2 0 1 1 2 5 3 4 6\nparm u 0 1 2\nend\n";
    ASSERT_TRUE(read_obj_patches(text).ok());
    ObjPatchReadOptions options;
    options.max_patches = 1;
    auto patches = read_obj_patches(text, options);
    ASSERT_FALSE(patches.ok());
    EXPECT_EQ(patches.error().code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(patches.error().line, 9);
    options = {};
    options.max_vertices = 5;
    auto vertices = read_obj_patches(text, options);
    ASSERT_FALSE(vertices.ok());
    EXPECT_EQ(vertices.error().code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(vertices.error().line, 6);
}

//! A B-spline surface as an OBJ `cstype [rat] bspline` surface: its net as `v x y z w` lines, the knot vectors as
//! `parm u` / `parm v`, the surf range its domain.
std::string bspline_obj(const BSplineSurface& s) {
    std::string out = "# a NURBS surface\n";
    for (std::size_t k = 0; k < s.points.size(); ++k)
        out += "v " + number(s.points[k].x) + " " + number(s.points[k].y) + " " + number(s.points[k].z) +
               (s.rational() ? " " + number(s.weights[k]) : std::string()) + "\n";
    out += s.rational() ? "cstype rat bspline\n" : "cstype bspline\n";
    out += "deg " + std::to_string(s.degree_u) + " " + std::to_string(s.degree_v) + "\n";
    const auto [u0, u1] = domain_u(s);
    const auto [v0, v1] = domain_v(s);
    out += "surf " + number(u0) + " " + number(u1) + " " + number(v0) + " " + number(v1);
    for (std::size_t k = 0; k < s.points.size(); ++k) out += " " + std::to_string(k + 1);
    out += "\nparm u";
    for (double t : s.knots_u) out += " " + number(t);
    out += "\nparm v";
    for (double t : s.knots_v) out += " " + number(t);
    return out + "\nend\n";
}

TEST(ObjBspline, SphereAndRandomSurfacesReadAsTheirBezierPatches) {
    std::vector<BSplineSurface> surfaces = {testing::sphere({1, 2, 3}, 1.5), testing::torus({0, 0, 0}, 3, 1)};
    for (unsigned seed = 1; seed <= 20; ++seed) surfaces.push_back(testing::random_surface(seed));
    for (const BSplineSurface& s : surfaces) {
        const std::string obj = bspline_obj(s);
        auto read = read_obj_patches(obj);
        ASSERT_TRUE(read.ok()) << read.error().message << "\n" << obj;
        auto expected = to_bezier(s);
        ASSERT_TRUE(expected.ok());
        ASSERT_EQ(read->patches.size(), expected->patches.size());
        for (std::size_t k = 0; k < read->patches.size(); ++k) {
            EXPECT_EQ(read->patches[k].points, expected->patches[k].points) << "patch " << k;
            EXPECT_EQ(read->patches[k].weights, expected->patches[k].weights) << "patch " << k;
            ASSERT_TRUE(read->patches[k].corner_uvs && expected->patches[k].corner_uvs);
            for (std::size_t c = 0; c < 4; ++c) {
                EXPECT_EQ((*read->patches[k].corner_uvs)[c].x, (*expected->patches[k].corner_uvs)[c].x);
                EXPECT_EQ((*read->patches[k].corner_uvs)[c].y, (*expected->patches[k].corner_uvs)[c].y);
            }
        }
    }
    // the sphere read from OBJ tessellates into a closed mesh on the sphere
    auto sphere = read_obj_patches(bspline_obj(testing::sphere({1, 2, 3}, 1.5)));
    ASSERT_TRUE(sphere.ok());
    TessellationOptions options;
    options.tolerance = 1e-3;
    auto mesh = tessellate_patches(sphere->patches, options);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_TRUE(testing::is_watertight(mesh->mesh));
    for (const Vec3& p : mesh->mesh.positions) EXPECT_NEAR(norm(p - Vec3{1, 2, 3}), 1.5, 1e-12);
}

TEST(ObjBspline, ErrorsNameTheLine) {
    // lines 1-6: a 3 x 2 net; 7 cstype; 8 deg; 9 surf; 10 parm u; 11 parm v; 12 end
    const std::string net = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 1\nv 2 1 0\n";
    const std::string surf = "surf 0 2 0 1 1 2 3 4 5 6\n";
    const auto file = [&](const std::string& parm_u, const std::string& parm_v, const std::string& head = "",
                          const std::string& s = "") {
        return net + (head.empty() ? "cstype bspline\ndeg 1 1\n" : head) + (s.empty() ? surf : s) + parm_u + parm_v +
               "end\n";
    };
    const std::string u = "parm u 0 0 1 2 2\n", v = "parm v 0 0 1 1\n";
    ASSERT_TRUE(read_obj_patches(file(u, v)).ok()) << read_obj_patches(file(u, v)).error().message;
    const BadCase cases[] = {
        {file("parm u 0 0 0 2 2\n", v), ErrorCode::InvalidArgument, 10, "parm u[2]: the value 0 is repeated 3 times"},
        {file("parm u 0 1 0.5 2 2\n", v), ErrorCode::ParseError, 10, "parm u values must not decrease"},
        {file("parm u 0 0 1 1.5 2 2\n", v), ErrorCode::ParseError, 9, "make a net of 4 x 2 = 8"},
        {file("parm u 0 0 2\n", v), ErrorCode::InvalidArgument, 10, "needs at least 4"},
        {file("", v), ErrorCode::ParseError, 9, "needs parm u"},
        {file(u, v, "", "surf 0 1.5 0 1 1 2 3 4 5 6\n"), ErrorCode::Unsupported, 9, "knot vectors' domain"},
        {file(u, v, "cstype rat bspline\ndeg 1 1\n").replace(0, 7, "v 0 0 0 -1"), ErrorCode::InvalidArgument, 9,
         "weight 0 (i 0, j 0) must be a finite number > 0"},
        {file(u, v, "cstype bspline\ndeg 1 1\n") + "trim 0 1 1\n", ErrorCode::Unsupported, 13, "trimming"},
    };
    for (const BadCase& c : cases) {
        auto result = read_obj_patches(c.text);
        ASSERT_FALSE(result.ok()) << c.text;
        EXPECT_EQ(result.error().code, c.code) << c.text << " -> " << result.error().message;
        EXPECT_EQ(result.error().line, c.line) << c.text << " -> " << result.error().message;
        EXPECT_NE(result.error().message.find(c.message), std::string::npos) << result.error().message;
    }
    // the Bézier patch budget from the knot vectors, before decomposing: 2 patches
    ObjPatchReadOptions options;
    options.max_patches = 1;
    auto budget = read_obj_patches(file(u, v), options);
    ASSERT_FALSE(budget.ok());
    EXPECT_EQ(budget.error().code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(budget.error().line, 9);
    // and their control points (2 x 4) against the vertex budget: the net has 6 vertices
    ObjPatchReadOptions few;
    few.max_vertices = 7;
    auto points = read_obj_patches(file(u, v), few);
    ASSERT_FALSE(points.ok());
    EXPECT_EQ(points.error().code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(points.error().line, 9);
    EXPECT_NE(points.error().message.find("Bézier patches have 8"), std::string::npos) << points.error().message;
}

}  // namespace
}  // namespace surfaced
