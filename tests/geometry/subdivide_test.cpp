// Our Catmull-Clark and Loop against OpenSubdiv Far, built in the same binary: same counts, same faces (index for
// index: our numbering is OpenSubdiv's), positions within 1e-9 of the bounding-box diagonal. Plus invariants that
// hold whatever the reference says: Euler characteristic, boundary loops, watertightness, predicted counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <limits>
#include <tuple>
#include <string>

#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/subdivide.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/osd_reference.h"

namespace surfaced {
namespace {

using testing::osd_subdivide;

struct NamedShape {
    std::string name;
    std::function<PolygonMesh()> make;
    bool triangles;
};

std::vector<NamedShape> all_shapes() {
    return {
        {"cube", shapes::cube, false},
        {"open_grid", [] { return shapes::grid(5, 4); }, false},
        {"open_grid_tri", [] { return shapes::grid(4, 3, true); }, true},
        {"mixed_polygons", shapes::mixed_polygons, false},
        {"tetrahedron", shapes::tetrahedron, true},
        {"octahedron", shapes::octahedron, true},
        {"icosahedron", shapes::icosahedron, true},
        {"torus", [] { return shapes::torus(8, 6); }, false},
        {"irregular_torus", shapes::irregular_torus, false},
        {"grid_with_holes", shapes::grid_with_holes, false},
    };
}

// Deterministic jitter so that no position is special (symmetric meshes can hide wrong weights).
PolygonMesh jittered(PolygonMesh m) {
    std::uint32_t state = 12345;
    for (Vec3& p : m.positions)
        for (int i = 0; i < 3; ++i) {
            state = state * 1664525u + 1013904223u;
            p[i] += 0.05 * (static_cast<double>(state >> 8) / double(1 << 24) - 0.5);
        }
    return m;
}

void expect_same_as_opensubdiv(const PolygonMesh& input, const SubdivisionOptions& options) {
    auto ours = subdivide(input, options);
    ASSERT_TRUE(ours.ok()) << ours.error().message;
    const PolygonMesh ref = osd_subdivide(input, options);
    ASSERT_EQ(ours->vertex_count(), ref.vertex_count());
    ASSERT_EQ(ours->face_count(), ref.face_count());
    ASSERT_EQ(ours->face_offsets, ref.face_offsets);
    ASSERT_EQ(ours->face_indices, ref.face_indices);
    const double tolerance = 1e-9 * input.bounds().diagonal();
    double worst = 0;
    for (std::size_t v = 0; v < ref.vertex_count(); ++v)
        worst = std::max(worst, norm(ours->positions[v] - ref.positions[v]));
    EXPECT_LE(worst, tolerance);
}

class SubdivisionVsOpenSubdiv
    : public ::testing::TestWithParam<std::tuple<std::size_t, SubdivisionScheme, BoundaryInterpolation, int>> {};

TEST_P(SubdivisionVsOpenSubdiv, SameTopologyAndPositions) {
    const auto [shape_index, scheme, boundary, levels] = GetParam();
    const auto shapes_list = all_shapes();
    const NamedShape& shape = shapes_list[shape_index];
    SubdivisionOptions options;
    options.scheme = scheme;
    options.levels = levels;
    options.boundary = boundary;
    expect_same_as_opensubdiv(jittered(shape.make()), options);
}

std::string param_name(const ::testing::TestParamInfo<SubdivisionVsOpenSubdiv::ParamType>& info) {
    const auto [shape_index, scheme, boundary, levels] = info.param;
    const char* b = boundary == BoundaryInterpolation::None       ? "none"
                    : boundary == BoundaryInterpolation::EdgeOnly ? "edgeonly"
                                                                  : "edgeandcorner";
    return all_shapes()[shape_index].name + (scheme == SubdivisionScheme::Loop ? "_loop_" : "_catmark_") + b + "_l" +
           std::to_string(levels);
}

// Every shape with Catmull-Clark; the triangle shapes also with Loop (Loop on polygons is an error, tested below).
std::vector<SubdivisionVsOpenSubdiv::ParamType> comparison_cases() {
    std::vector<SubdivisionVsOpenSubdiv::ParamType> cases;
    const auto shapes = all_shapes();
    for (std::size_t s = 0; s < shapes.size(); ++s)
        for (auto scheme : {SubdivisionScheme::CatmullClark, SubdivisionScheme::Loop}) {
            if (scheme == SubdivisionScheme::Loop && !shapes[s].triangles) continue;
            for (auto boundary :
                 {BoundaryInterpolation::EdgeOnly, BoundaryInterpolation::EdgeAndCorner, BoundaryInterpolation::None})
                for (int levels = 1; levels <= 4; ++levels) cases.emplace_back(s, scheme, boundary, levels);
        }
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Shapes, SubdivisionVsOpenSubdiv, ::testing::ValuesIn(comparison_cases()), param_name);

TEST(Subdivision, InvariantsHoldAcrossLevels) {
    for (const NamedShape& shape : all_shapes()) {
        const PolygonMesh input = shape.make();
        const auto chi = testing::euler_characteristic(input);
        const auto loops = testing::boundary_loop_count(input);
        for (auto scheme : {SubdivisionScheme::CatmullClark, SubdivisionScheme::Loop}) {
            if (scheme == SubdivisionScheme::Loop && !shape.triangles) continue;
            for (int levels = 1; levels <= 3; ++levels) {
                SubdivisionOptions options;
                options.scheme = scheme;
                options.levels = levels;
                auto out = subdivide(input, options);
                ASSERT_TRUE(out.ok()) << shape.name;
                EXPECT_EQ(testing::euler_characteristic(*out), chi) << shape.name;
                EXPECT_EQ(testing::boundary_loop_count(*out), loops) << shape.name;
                EXPECT_EQ(testing::is_watertight(*out), testing::is_watertight(input)) << shape.name;
                EXPECT_EQ(testing::edge_stats(*out).inconsistent_edges, 0u) << shape.name;
                EXPECT_EQ(out->face_count(), predicted_face_count(input, scheme, levels)) << shape.name;
                EXPECT_EQ(out->vertex_count(), predicted_vertex_count(input, scheme, levels)) << shape.name;
                EXPECT_TRUE(validate(*out).ok()) << shape.name;
            }
        }
    }
}

TEST(Subdivision, CatmullClarkCubeMatchesClosedFormAndShrinksMonotonically) {
    // One level, cube corner (-1/2,-1/2,-1/2), valence 3: (n-2)/n P + (sum of edge neighbours + face points)/n^2.
    // Per axis: P = -1/2, edge neighbours sum to -1/2, face points sum to -1/2, so -1/6 - 1/9 = -5/18.
    auto one = subdivide(shapes::cube(), SubdivisionOptions{});
    ASSERT_TRUE(one.ok());
    EXPECT_NEAR(one->positions[0].x, -5.0 / 18.0, 1e-15);
    EXPECT_NEAR(one->positions[0].y, -5.0 / 18.0, 1e-15);
    EXPECT_NEAR(one->positions[0].z, -5.0 / 18.0, 1e-15);
    // A convex control mesh: every level lies inside the previous one, so the volume strictly decreases.
    double previous = testing::signed_volume(shapes::cube());
    EXPECT_NEAR(previous, 1.0, 1e-15);
    for (int levels = 1; levels <= 4; ++levels) {
        SubdivisionOptions options;
        options.levels = levels;
        auto out = subdivide(shapes::cube(), options);
        ASSERT_TRUE(out.ok());
        for (std::size_t f = 0; f < out->face_count(); ++f) ASSERT_EQ(out->face_size(f), 4u);
        const double volume = testing::signed_volume(*out);
        EXPECT_LT(volume, previous);
        EXPECT_GT(volume, 0.0);
        previous = volume;
    }
}

TEST(Subdivision, LoopRejectsNonTrianglesNamingTheFace) {
    PolygonMesh m = shapes::mixed_polygons();
    SubdivisionOptions options;
    options.scheme = SubdivisionScheme::Loop;
    auto out = subdivide(m, options);
    ASSERT_FALSE(out.ok());
    EXPECT_EQ(out.error().code, ErrorCode::NotTriangleMesh);
    EXPECT_EQ(out.error().element, 0);
    EXPECT_NE(out.error().message.find("face 0"), std::string::npos);
}

TEST(Subdivision, RejectsInvalidInput) {
    PolygonMesh m = shapes::cube();
    m.face_indices[5] = 42;
    auto out = subdivide(m, SubdivisionOptions{});
    ASSERT_FALSE(out.ok());
    EXPECT_EQ(out.error().code, ErrorCode::IndexOutOfRange);
    SubdivisionOptions negative;
    negative.levels = -1;
    EXPECT_EQ(subdivide(shapes::cube(), negative).error().code, ErrorCode::InvalidArgument);
}

// Faces that repeat a vertex, as OpenSubdiv refines them: a corner followed by the same vertex is a degenerate edge of
// its own; an edge a face uses twice gets a second instance (found again by later faces as the first one, and by a
// crease tag); all of them non-manifold, so infinitely sharp. Built into small grids, compared with OpenSubdiv in every
// boundary mode and crease method.
PolygonMesh with_face(PolygonMesh m, std::size_t f, std::initializer_list<Index> verts) {
    std::size_t k = m.face_offsets[f];
    for (Index v : verts) m.face_indices[k++] = v;
    return m;
}

TEST(Subdivision, FacesThatRepeatAVertexMatchOpenSubdiv) {
    const PolygonMesh quads = jittered(shapes::grid(3, 3));  // vertex (i, j) is 4j + i; face 4 is the middle one
    const PolygonMesh tris = jittered(shapes::grid(3, 3, true));
    PolygonMesh folded_creased = with_face(quads, 4, {5, 6, 5, 9});
    folded_creased.tags.creases = {{5, 6, 2.5}, {9, 5, 1.5}, {6, 10, 3.0}};
    folded_creased.tags.corners = {{5, 0.5}};
    PolygonMesh pinched_hole = with_face(quads, 4, {5, 6, 10, 10});
    pinched_hole.tags.holes = {4};
    PolygonMesh tri_folded_creased = with_face(tris, 8, {5, 10, 5});
    tri_folded_creased.tags.creases = {{5, 10, 2.0}};
    const PolygonMesh cube = shapes::cube();
    const auto c2 = cube.face(2);
    const std::tuple<const char*, PolygonMesh, bool> cases[] = {
        {"pinched quad (degenerate edge)", with_face(quads, 4, {5, 6, 10, 10}), false},
        {"folded quad (an edge used twice, joined by a neighbour)", with_face(quads, 4, {5, 6, 5, 9}), false},
        {"folded quad with creases on the repeated edges", folded_creased, false},
        {"pinched hole", pinched_hole, false},
        {"quad of one vertex", with_face(quads, 4, {5, 5, 5, 5}), false},
        {"pinched closed cube", jittered(with_face(cube, 2, {c2[0], c2[1], c2[1], c2[3]})), false},
        {"pinched triangle, Loop", with_face(tris, 8, {5, 10, 10}), true},
        {"pinched triangle, Catmull-Clark", with_face(tris, 8, {5, 10, 10}), false},
        {"triangle of one vertex, Loop", with_face(tris, 8, {5, 5, 5}), true},
        {"folded triangle with a crease, Loop", tri_folded_creased, true},
    };
    for (const auto& [name, mesh, loop] : cases) {
        ASSERT_FALSE(validate(mesh).ok()) << name << ": the case must really repeat a vertex";
        ASSERT_TRUE(validate_for_subdivision(mesh).ok()) << name;
        for (auto method : {CreaseMethod::Uniform, CreaseMethod::Chaikin})
            for (auto boundary :
                 {BoundaryInterpolation::None, BoundaryInterpolation::EdgeOnly, BoundaryInterpolation::EdgeAndCorner})
                for (int levels = 1; levels <= 3; ++levels) {
                    SCOPED_TRACE(std::string(name) + ", level " + std::to_string(levels));
                    SubdivisionOptions options;
                    options.scheme = loop ? SubdivisionScheme::Loop : SubdivisionScheme::CatmullClark;
                    options.levels = levels;
                    options.crease_method = method;
                    options.boundary = boundary;
                    expect_same_as_opensubdiv(mesh, options);
                }
    }
}

// Random small meshes whose faces often repeat vertices (and share edges every which way), with random creases,
// corners, holes, boundary modes and crease methods: wherever both accept the input, we and OpenSubdiv agree.
TEST(Subdivision, RandomFacesWithRepeatedVerticesMatchOpenSubdiv) {
    std::uint32_t state = 2026;
    auto next = [&](std::uint32_t n) {
        state = state * 1664525u + 1013904223u;
        return (state >> 8) % n;
    };
    int compared = 0, with_repeats = 0;
    for (int iteration = 0; iteration < 400; ++iteration) {
        PolygonMesh m;
        const std::uint32_t nv = 3 + next(8);
        for (std::uint32_t v = 0; v < nv; ++v)
            m.positions.push_back({next(1000) / 100.0, next(1000) / 100.0, next(1000) / 100.0});
        const bool loop = next(2) == 1;
        const std::uint32_t nf = 1 + next(6);
        for (std::uint32_t f = 0; f < nf; ++f) {
            std::vector<Index> face(loop ? 3 : 3 + next(3));
            for (Index& v : face) v = next(nv);
            m.add_face(face);
        }
        if (next(3) == 0) m.tags.creases.push_back({m.face_indices[0], m.face_indices[1], next(40) / 10.0});
        if (next(3) == 0) m.tags.corners.push_back({next(nv), next(40) / 10.0});
        if (next(4) == 0) m.tags.holes.push_back(next(nf));
        SubdivisionOptions options;
        options.scheme = loop ? SubdivisionScheme::Loop : SubdivisionScheme::CatmullClark;
        options.levels = 1 + static_cast<int>(next(3));
        options.boundary = static_cast<BoundaryInterpolation>(next(3));
        options.crease_method = next(2) == 1 ? CreaseMethod::Chaikin : CreaseMethod::Uniform;
        auto ours = subdivide(m, options);
        if (!ours.ok()) continue;  // a crease between vertices that share no edge: OpenSubdiv warns and ignores it
        const PolygonMesh ref = osd_subdivide(m, options);
        ASSERT_FALSE(ref.positions.empty()) << "OpenSubdiv refused what we refined, iteration " << iteration;
        ++compared;
        with_repeats += !validate(m).ok();
        ASSERT_EQ(ours->vertex_count(), ref.vertex_count()) << iteration;
        ASSERT_EQ(ours->face_indices, ref.face_indices) << iteration;
        double worst = 0;
        for (std::size_t v = 0; v < ref.vertex_count(); ++v)
            worst = std::max(worst, norm(ours->positions[v] - ref.positions[v]));
        EXPECT_LE(worst, 1e-9 * m.bounds().diagonal()) << iteration;
    }
    EXPECT_GE(compared, 300);
    EXPECT_GE(with_repeats, 150);  // most random faces repeat a vertex: the test is about them
}

// What is really invalid stays a clear error naming the face: too few vertices, an index out of range, also when
// another face repeats a vertex (the lenient check must not stop at the first repeat).
TEST(Subdivision, RepeatedVerticesAreAllowedButBrokenFacesAreNot) {
    PolygonMesh m = with_face(shapes::grid(3, 3), 4, {5, 6, 10, 10});
    EXPECT_TRUE(subdivide(m, SubdivisionOptions{}).ok());
    PolygonMesh out_of_range = m;
    out_of_range.face_indices[out_of_range.face_offsets[7] + 2] = 99;
    auto range = subdivide(out_of_range, SubdivisionOptions{});
    ASSERT_FALSE(range.ok());
    EXPECT_EQ(range.error().code, ErrorCode::IndexOutOfRange);
    EXPECT_EQ(range.error().element_kind, ElementKind::Face);
    EXPECT_EQ(range.error().element, 7);
    PolygonMesh two_vertices = m;  // face 8 keeps only two of its vertices
    two_vertices.face_indices.erase(two_vertices.face_indices.begin() + two_vertices.face_offsets[8] + 2,
                                    two_vertices.face_indices.end());
    two_vertices.face_offsets.back() = static_cast<Index>(two_vertices.face_indices.size());
    auto short_face = subdivide(two_vertices, SubdivisionOptions{});
    ASSERT_FALSE(short_face.ok());
    EXPECT_EQ(short_face.error().code, ErrorCode::DegenerateFace);
    EXPECT_EQ(short_face.error().element, 8);
    PolygonMesh bad_crease = m;
    bad_crease.tags.creases = {{5, 6, 1.0}, {0, 42, 1.0}};
    auto crease = subdivide(bad_crease, SubdivisionOptions{});
    ASSERT_FALSE(crease.ok());
    EXPECT_EQ(crease.error().code, ErrorCode::IndexOutOfRange);
    EXPECT_EQ(crease.error().element_kind, ElementKind::Crease);
    EXPECT_EQ(crease.error().element, 1);
    PolygonMesh bad_hole = m;
    bad_hole.tags.holes = {9};
    EXPECT_EQ(subdivide(bad_hole, SubdivisionOptions{}).error().element_kind, ElementKind::Hole);
    PolygonMesh nan = m;
    nan.positions[3].y = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(subdivide(nan, SubdivisionOptions{}).error().code, ErrorCode::NonFinite);
}

TEST(Subdivision, LevelZeroIsIdentity) {
    SubdivisionOptions options;
    options.levels = 0;
    auto out = subdivide(shapes::cube(), options);
    ASSERT_TRUE(out.ok());
    EXPECT_EQ(out->face_indices, shapes::cube().face_indices);
}

TEST(Subdivision, PredictionSaturatesInsteadOfOverflowing) {
    EXPECT_EQ(predicted_face_count(shapes::cube(), SubdivisionScheme::CatmullClark, 40), UINT64_MAX);
    SubdivisionOptions options;
    options.levels = 20;
    auto out = subdivide(shapes::cube(), options);
    ASSERT_FALSE(out.ok());
    EXPECT_EQ(out.error().code, ErrorCode::BudgetExceeded);
}

}  // namespace
}  // namespace surfaced

namespace surfaced {
namespace {

PolygonMesh triangulated_torus() {
    const PolygonMesh quads = shapes::torus(8, 6);
    PolygonMesh m;
    m.positions = quads.positions;
    for (std::size_t f = 0; f < quads.face_count(); ++f) {
        auto q = quads.face(f);
        m.add_face({q[0], q[1], q[2]});
        m.add_face({q[0], q[2], q[3]});
    }
    return m;
}

TEST(LoopWarren, EqualsLoopWhereEveryVertexIsRegular) {
    const PolygonMesh torus = triangulated_torus();  // every vertex has valence 6
    SubdivisionOptions loop, warren;
    loop.scheme = warren.scheme = SubdivisionScheme::Loop;
    loop.levels = warren.levels = 2;
    warren.loop_weights = LoopWeights::Warren;
    auto a = subdivide(torus, loop), b = subdivide(torus, warren);
    ASSERT_TRUE(a.ok() && b.ok());
    for (std::size_t v = 0; v < a->vertex_count(); ++v) EXPECT_LE(norm(a->positions[v] - b->positions[v]), 1e-15);
}

TEST(LoopWarren, UsesThreeOverEightNAndDiffersFromLoopAtIrregularVertices) {
    const PolygonMesh ico = shapes::icosahedron();  // valence 5 everywhere
    SubdivisionOptions options;
    options.scheme = SubdivisionScheme::Loop;
    options.loop_weights = LoopWeights::Warren;
    auto out = subdivide(ico, options);
    ASSERT_TRUE(out.ok());
    // vertex 0's neighbours in the icosahedron
    Vec3 sum{};
    std::vector<Index> neighbours;
    for (std::size_t f = 0; f < ico.face_count(); ++f) {
        auto t = ico.face(f);
        for (int k = 0; k < 3; ++k)
            if (t[k] == 0)
                for (Index n : {t[(k + 1) % 3], t[(k + 2) % 3]})
                    if (std::find(neighbours.begin(), neighbours.end(), n) == neighbours.end()) neighbours.push_back(n);
    }
    ASSERT_EQ(neighbours.size(), 5u);
    for (Index n : neighbours) sum += ico.positions[n];
    const double beta = 3.0 / 40.0;
    const Vec3 expected = (1.0 - 5 * beta) * ico.positions[0] + beta * sum;
    EXPECT_LE(norm(out->positions[0] - expected), 1e-15);
    options.loop_weights = LoopWeights::Loop;
    EXPECT_GT(norm(subdivide(ico, options)->positions[0] - expected), 1e-3);
}

// The limit masks are the fixed point of refinement: a vertex's limit evaluated at level 1 must agree with its
// position after many more levels (the distance shrinks by the subdominant eigenvalue each level).
TEST(LimitSurface, LimitMasksAreTheFixedPointOfRefinement) {
    const std::pair<SubdivisionScheme, LoopWeights> cases[] = {{SubdivisionScheme::CatmullClark, LoopWeights::Loop},
                                                               {SubdivisionScheme::Loop, LoopWeights::Loop},
                                                               {SubdivisionScheme::Loop, LoopWeights::Warren}};
    for (const auto& [scheme, weights] : cases) {
        const PolygonMesh mesh = scheme == SubdivisionScheme::Loop ? shapes::icosahedron() : shapes::irregular_torus();
        SubdivisionOptions options;
        options.scheme = scheme;
        options.loop_weights = weights;
        options.levels = 1;
        options.limit_surface = true;
        auto limit = subdivide(mesh, options);
        options.limit_surface = false;
        options.levels = 7;
        auto fine = subdivide(mesh, options);
        ASSERT_TRUE(limit.ok() && fine.ok());
        double worst = 0;
        for (std::size_t v = 0; v < limit->vertex_count(); ++v)
            worst = std::max(worst, norm(limit->positions[v] - fine->positions[v]));
        std::printf("[limit fixed point] %s: %.3g of the diagonal\n",
                    scheme == SubdivisionScheme::Loop ? "loop" : "catmark", worst / mesh.bounds().diagonal());
        EXPECT_LE(worst, 1e-4 * mesh.bounds().diagonal()) << (scheme == SubdivisionScheme::Loop ? "loop" : "catmark");
    }
}

}  // namespace
}  // namespace surfaced

namespace surfaced {
namespace {

TEST(SubdivisionThreads, TwoThreadsGiveBitIdenticalResults) {
    // large enough that every level is split in two (kSplitMinimum), with creases so the sharp paths run too
    PolygonMesh mesh = shapes::torus(160, 120);
    mesh.tags.creases = {{0, 1, 2.5}, {1, 2, 10}, {120, 121, 0.5}};
    mesh.tags.corners = {{5, 1.5}};
    for (auto scheme : {SubdivisionScheme::CatmullClark, SubdivisionScheme::Loop}) {
        PolygonMesh input = mesh;
        if (scheme == SubdivisionScheme::Loop) {
            PolygonMesh tris;
            tris.positions = mesh.positions;
            tris.tags = mesh.tags;
            for (std::size_t f = 0; f < mesh.face_count(); ++f) {
                auto q = mesh.face(f);
                tris.add_face({q[0], q[1], q[2]});
                tris.add_face({q[0], q[2], q[3]});
            }
            input = tris;
        }
        SubdivisionOptions one, two;
        one.scheme = two.scheme = scheme;
        one.levels = two.levels = 2;
        one.threads = 1;
        two.threads = 2;
        auto a = subdivide(input, one), b = subdivide(input, two);
        ASSERT_TRUE(a.ok() && b.ok());
        ASSERT_EQ(a->face_indices, b->face_indices);
        ASSERT_EQ(a->positions.size(), b->positions.size());
        for (std::size_t v = 0; v < a->positions.size(); ++v) ASSERT_EQ(a->positions[v], b->positions[v]) << v;
    }
}

}  // namespace
}  // namespace surfaced
