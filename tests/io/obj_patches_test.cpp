// OBJ free-form Bézier and B-spline surfaces (geometry/io/obj_patches.h): the teapot written as `cstype bezier`
// surfaces tessellates exactly as its BEZ form; multi-segment surfaces split into patches sharing their boundary
// control points; rational surfaces take the vertices' w; `cstype [rat] bspline` surfaces (the NURBS sphere, torus,
// random surfaces) read as their Bézier decomposition; curv2 curves trim surfaces through trim and hole statements
// (the loops read back curve by curve, the trimmed area against the analytic one); everything refused names its line.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <string>

#include "geometry/io/bez.h"
#include "geometry/io/obj_patches.h"
#include "geometry/surfaces/bspline_surface.h"
#include "geometry/surfaces/trimmed_surface.h"
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
        {header + "cstype bezier\ndeg 1 1\n" + quad + "trim 0 1 1\nend\n", ErrorCode::ParseError, 8,
         "not one of the 0 curv2 curves defined so far"},
        {header + "cstype bezier\ndeg 1 1\n" + quad + "sp 1\nend\n", ErrorCode::Unsupported, 8, "special"},
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
        {file(u, v, "cstype bspline\ndeg 1 1\n") + "trim 0 1 1\n", ErrorCode::ParseError, 13, "trim outside a surf"},
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

double mesh_area(const PolygonMesh& mesh) {
    double sum = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t k = 1; k + 1 < face.size(); ++k)
            sum += 0.5 * norm(cross(mesh.positions[face[k]] - mesh.positions[face[0]],
                                    mesh.positions[face[k + 1]] - mesh.positions[face[0]]));
    }
    return sum;
}

//! The plane z = 0 over [0, 2]^2, degree 1 x 1, as a bspline or a bezier surf over [0, 1]^2; `loops` are its trim
//! and hole statements. Curves: curv2 1-4 the sides of the square [0.25, 0.75]^2 counter-clockwise (linear bezier),
//! curv2 5 the circle about (0.5, 0.5) of radius 0.1 (rational quadratic bspline, NURBS Book ex. 7.2). Lines: 1-4 v,
//! 5-16 vp, 17 cstype, 18 deg 1, 19-26 the four curv2 blocks, 27 cstype rat bspline, 28 deg 2, 29 curv2, 30 parm u,
//! 31 end, 32 cstype, 33 deg 1 1, 34 surf, 35 parm u, 36 parm v, then the loops from 37.
std::string trimmed_plane(const std::string& loops, const std::string& surface_type = "bspline") {
    std::string text = "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 2 2 0\n";
    text += "vp 0.25 0.25\nvp 0.75 0.25\nvp 0.75 0.75\nvp 0.25 0.75\n";
    const std::string h = " 0.70710678118654757\n";
    text += "vp 0.6 0.5 1\nvp 0.6 0.6" + h + "vp 0.5 0.6 1\nvp 0.4 0.6" + h;
    text += "vp 0.4 0.5 1\nvp 0.4 0.4" + h + "vp 0.5 0.4 1\nvp 0.6 0.4" + h;
    text += "cstype bezier\ndeg 1\n";
    text += "curv2 1 2\nend\ncurv2 2 3\nend\ncurv2 3 4\nend\ncurv2 4 1\nend\n";
    text += "cstype rat bspline\ndeg 2\n";
    text += "curv2 5 6 7 8 9 10 11 12 5\nparm u 0 0 0 0.25 0.25 0.5 0.5 0.75 0.75 1 1 1\nend\n";
    text += "cstype " + surface_type + "\ndeg 1 1\n";
    text += "surf 0 1 0 1 1 2 3 4\n";
    text += surface_type == "bspline" ? "parm u 0 0 1 1\nparm v 0 0 1 1\n" : "parm u 0 1\nparm v 0 1\n";
    return text + loops + "end\n";
}

TEST(ObjTrim, Curv2TrimAndHoleStatements) {
    // the square clockwise: each side backwards (u0 u1 = 1 0), the last one by a relative index (-5 of 5: curv2 1)
    for (const char* type : {"bspline", "bezier"}) {
        SCOPED_TRACE(type);
        auto read = read_obj_surfaces(trimmed_plane("trim 1 0 4 1 0 3 1 0 2 1 0 -5\nhole 0 1 5\n", type));
        ASSERT_TRUE(read.ok()) << read.error().message;
        EXPECT_TRUE(read->patches.patches.empty());
        ASSERT_EQ(read->trimmed.size(), 1u);
        EXPECT_EQ(read->trimmed[0].line, 34);
        const TrimmedSurface& t = read->trimmed[0].trimmed;
        EXPECT_EQ(t.surface.knots_u, (std::vector<double>{0, 0, 1, 1}));
        ASSERT_EQ(t.outer.size(), 1u);
        ASSERT_EQ(t.outer[0].curves.size(), 4u);
        ASSERT_EQ(t.holes.size(), 1u);
        // curv2 4 runs from (0.25, 0.75) to (0.25, 0.25); backwards it starts at (0.25, 0.25)
        const TrimCurve& back = t.outer[0].curves[0];
        EXPECT_EQ(back.points.front().y, 0.25);
        EXPECT_EQ(back.points.back().y, 0.75);
        EXPECT_EQ(back.knots, (std::vector<double>{0, 0, 1, 1}));
        const TrimCurve& circle = t.holes[0].curves[0];
        EXPECT_EQ(circle.degree, 2);
        ASSERT_EQ(circle.weights.size(), 9u);
        EXPECT_EQ(circle.weights[1], 0.70710678118654757);
        // [0.5, 1.5]^2 on the plane less the circle of radius 0.2: the inscribed polygon is within e of the circle
        TrimmedTessellationOptions options;
        options.tolerance = 1e-3;
        auto mesh = tessellate(t, options);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        const double exact = 1 - std::numbers::pi * 0.04;
        EXPECT_NEAR(mesh_area(mesh->mesh), exact, 2 * std::numbers::pi * 0.2 * options.tolerance);
        EXPECT_LE(mesh->bound, options.tolerance);
    }
    // a bezier surf of 2 x 1 segments becomes the B-spline whose interior break has multiplicity degree (1)
    std::string two = trimmed_plane("trim 0 1 1 0 1 2 0 1 3 0 1 4\n", "bezier");
    two.replace(two.find("v 2 2 0\n"), 8, "v 2 2 0\nv 4 0 0\nv 4 2 0\n");
    two.replace(two.find("surf 0 1 0 1 1 2 3 4"), 20, "surf 0 2 0 1 1 2 5 3 4 6");
    two.replace(two.find("parm u 0 1\n"), 11, "parm u 0 1 2\n");
    auto read = read_obj_surfaces(two);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read->trimmed[0].trimmed.surface.knots_u, (std::vector<double>{0, 0, 1, 2, 2}));
    EXPECT_EQ(read->trimmed[0].trimmed.surface.count_u, 3);
}

TEST(ObjTrim, MultiSegmentBezierCurv2) {
    // the square as one linear bezier curv2 of four segments: knots 0 0 1 2 3 4 4 (interior breaks once, degree 1)
    std::string text = trimmed_plane("hole 0 4 5\n");  // curv2 5: the one inserted before the circle
    text.insert(text.find("cstype rat bspline"), "curv2 1 2 3 4 1\nparm u 0 1 2 3 4\nend\n");
    auto read = read_obj_surfaces(text);
    ASSERT_TRUE(read.ok()) << read.error().message;
    const TrimCurve& square = read->trimmed[0].trimmed.holes[0].curves[0];
    EXPECT_EQ(square.knots, (std::vector<double>{0, 0, 1, 2, 3, 4, 4}));
    ASSERT_EQ(square.points.size(), 5u);
    TrimmedTessellationOptions options;
    options.tolerance = 1e-2;
    auto mesh = tessellate(read->trimmed[0].trimmed, options);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_NEAR(mesh_area(mesh->mesh), 3.0, 1e-12);  // [0, 2]^2 less [0.5, 1.5]^2
    // five points make four segments of degree 1, not three
    text.replace(text.find("curv2 1 2 3 4 1"), 15, "curv2 1 2 3 4  ");
    auto short_curve = read_obj_surfaces(text);
    ASSERT_FALSE(short_curve.ok());
    EXPECT_EQ(short_curve.error().line, 27);
    EXPECT_NE(short_curve.error().message.find("with 4 segments needs 5"), std::string::npos)
        << short_curve.error().message;
}

//! `text` with the first `from` replaced by `to`.
std::string edit(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

TEST(ObjTrim, ErrorsNameTheLine) {
    const std::string square = "trim 0 1 1 0 1 2 0 1 3 0 1 4\n";
    const std::string plane = trimmed_plane(square);
    const BadCase cases[] = {
        {trimmed_plane(square + "hole 0 1 9\n"), ErrorCode::ParseError, 38, "not one of the 5 curv2"},
        {trimmed_plane("trim 0 0.5 1 0 1 2 0 1 3 0 1 4\n"), ErrorCode::Unsupported, 37,
         "only a whole curve is supported"},
        {trimmed_plane("trim 0 1 1 0 1 2 0 1 3\n"), ErrorCode::InvalidArgument, 37, "outer[0][2]"},
        {trimmed_plane("trim 0 1 1 0 1 2 0 1\n"), ErrorCode::ParseError, 37, "missing the curv2"},
        {trimmed_plane("trim\n"), ErrorCode::ParseError, 37, "needs u0 u1 curv2 triples"},
        // the circle as the outer loop and the square around it as a hole: the outer loop lies inside a hole
        {trimmed_plane("trim 0 1 5\nhole 0 1 1 0 1 2 0 1 3 0 1 4\n"), ErrorCode::InvalidArgument, 37,
         "outer[0]: lies inside holes[0]"},
        {"trim 0 1 1\n" + plane, ErrorCode::ParseError, 1, "outside a surf"},
        {edit(plane, "curv2 1 2\n", "curv2 1 22\n"), ErrorCode::ParseError, 19, "not one of the 12 parameter"},
        {edit(plane, "parm u 0 0 0 0.25", "parm u 0 0 0.25"), ErrorCode::ParseError, 30, "need 12"},
        {edit(plane, "vp 0.25 0.25\n", "vp 0.25\n"), ErrorCode::ParseError, 19, "has no v"},
        {edit(plane, "vp 0.6 0.5 1\n", "vp 0.6 0.5 0\n"), ErrorCode::InvalidArgument, 29, "curv2: weight"},
        {edit(plane, "parm u 0 0 0 0.25", "parm u 0 0 0 0   "), ErrorCode::InvalidArgument, 30, "curv2 parm u"},
        {edit(plane, "end\ncstype rat", "curv2 1 2\ncstype rat"), ErrorCode::ParseError, 26,
         "curv2 inside an open block"},
        {edit(plane, "parm v 0 0 1 1\n", "curv2 1 2\n"), ErrorCode::ParseError, 36, "curv2 inside an open block"},
        {edit(plane, "curv2 5 6", "curv2 5 6\nparm v 0 1"), ErrorCode::ParseError, 30, "a curv2 has only parm u"},
    };
    for (const BadCase& c : cases) {
        auto result = read_obj_surfaces(c.text);
        ASSERT_FALSE(result.ok()) << c.text;
        EXPECT_EQ(result.error().code, c.code) << c.text << " -> " << result.error().message;
        EXPECT_EQ(result.error().line, c.line) << c.text << " -> " << result.error().message;
        EXPECT_NE(result.error().message.find(c.message), std::string::npos) << result.error().message;
        EXPECT_NE(result.error().message.find("line " + std::to_string(c.line) + ": "), std::string::npos)
            << result.error().message;
    }
    // read_obj_patches has no place for trims: the surf's line
    auto patches = read_obj_patches(plane);
    ASSERT_FALSE(patches.ok());
    EXPECT_EQ(patches.error().code, ErrorCode::Unsupported);
    EXPECT_EQ(patches.error().line, 34);
    // budgets: trim and hole statements, and the chords of the validated polygons
    ObjPatchReadOptions options;
    options.max_trim_loops = 1;
    auto loops = read_obj_surfaces(trimmed_plane(square + "hole 0 1 5\n"), options);
    ASSERT_FALSE(loops.ok());
    EXPECT_EQ(loops.error().code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(loops.error().line, 38);
    options = {};
    options.max_trim_segments = 10;
    auto segments = read_obj_surfaces(trimmed_plane(square + "hole 0 1 5\n"), options);
    ASSERT_FALSE(segments.ok());
    EXPECT_EQ(segments.error().code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(segments.error().line, 38);
}

}  // namespace
}  // namespace surfaced
