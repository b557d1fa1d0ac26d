// repair_mesh: every output is manifold, consistently oriented, free of degenerate and duplicate faces and outward
// where closed (checked by tests/support/repair_asserts.h, independently of the library's own audit), and each step's
// count is what the case was built with. Cases: an STL-style soup, flipped and inside-out cubes, duplicates, a fin, a
// bow-tie, pinched cubes, degenerate faces, a sphere with a hole, small components, a mesh that needs nothing; then
// seeded random soups. The same cases as files, read by the service's readers: tests/io/repair_corpus_test.cpp.
#include "geometry/repair/repair.h"
#include "geometry/repair/open_seams.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <vector>

#include "geometry/mesh/normals.h"
#include "geometry/mesh/shapes.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/subdivision/subdivide.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/repair_asserts.h"

namespace surfaced {
namespace {

using testing::closed_component_volumes;
using testing::edge_stats;
using testing::expect_counts_add_up;
using testing::expect_repaired;
using testing::faces_by_edge;
using testing::is_watertight;
using testing::signed_volume;

RepairResult repaired(const PolygonMesh& mesh, const RepairOptions& options = {}) {
    auto result = repair_mesh(mesh, options);
    EXPECT_TRUE(result.ok()) << (result.ok() ? "" : result.error().message);
    if (!result.ok()) return {};
    expect_repaired(result->mesh, options.orient);
    expect_counts_add_up(mesh, *result);
    return std::move(result).value();
}

// ---- small generators ----

PolygonMesh cube() { return triangulate(shapes::cube()); }  // 8 vertices, 12 triangles, outward

//! Every triangle with its own three vertices, as an STL file has them.
PolygonMesh soup(const PolygonMesh& mesh) {
    PolygonMesh out;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        std::vector<Index> face;
        for (Index v : mesh.face(f)) {
            face.push_back(static_cast<Index>(out.positions.size()));
            out.positions.push_back(mesh.positions[v]);
        }
        out.add_face(face);
    }
    return out;
}

void reverse_faces(PolygonMesh& mesh, std::initializer_list<std::size_t> faces) {
    for (std::size_t f : faces)
        std::reverse(mesh.face_indices.begin() + mesh.face_offsets[f],
                     mesh.face_indices.begin() + mesh.face_offsets[f + 1]);
}

//! Appends `part` to `mesh` (its own vertices).
void append(PolygonMesh& mesh, const PolygonMesh& part, Vec3 offset = {}) {
    const auto base = static_cast<Index>(mesh.positions.size());
    for (const Vec3& p : part.positions) mesh.positions.push_back(p + offset);
    for (std::size_t f = 0; f < part.face_count(); ++f) {
        std::vector<Index> face;
        for (Index v : part.face(f)) face.push_back(base + v);
        mesh.add_face(face);
    }
}

//! Same faces, same windings, same positions, whatever the vertex numbering.
void expect_same_surface(const PolygonMesh& a, const PolygonMesh& b) {
    ASSERT_EQ(a.face_count(), b.face_count());
    EXPECT_EQ(a.vertex_count(), b.vertex_count());
    EXPECT_EQ(testing::surface_faces(a), testing::surface_faces(b));
}

RepairReport only(std::initializer_list<std::pair<std::size_t RepairReport::*, std::size_t>> counts,
                  std::size_t components) {
    RepairReport r;
    for (const auto& [field, value] : counts) r.*field = value;
    r.components = components;
    return r;
}

void expect_report(const RepairReport& got, const RepairReport& want) {
    EXPECT_EQ(got.welded, want.welded);
    EXPECT_EQ(got.degenerate, want.degenerate);
    EXPECT_EQ(got.duplicate, want.duplicate);
    EXPECT_EQ(got.flipped, want.flipped);
    EXPECT_EQ(got.nonmanifold_split, want.nonmanifold_split);
    EXPECT_EQ(got.small_components, want.small_components);
    EXPECT_EQ(got.removed_faces, want.removed_faces);
    EXPECT_EQ(got.holes_filled, want.holes_filled);
    EXPECT_EQ(got.fill_faces, want.fill_faces);
    EXPECT_EQ(got.unreferenced, want.unreferenced);
    EXPECT_EQ(got.components, want.components);
}

// ---- cases ----

TEST(Repair, TriangleSoupOfACubeWeldsIntoTheIndexedCube) {
    const PolygonMesh indexed = cube();
    const PolygonMesh stl = soup(indexed);
    ASSERT_EQ(stl.vertex_count(), 36u);
    const RepairResult r = repaired(stl);
    expect_report(r.report, only({{&RepairReport::welded, 36 - 8}}, 1));
    expect_same_surface(r.mesh, indexed);
    EXPECT_TRUE(is_watertight(r.mesh));
    EXPECT_NEAR(signed_volume(r.mesh), 1.0, 1e-12);
}

TEST(Repair, ReversesTheFacesThatDisagree) {
    for (auto flipped : {std::initializer_list<std::size_t>{1, 5, 8}, {0, 5, 8}}) {  // the seed face among them too
        PolygonMesh mesh = cube();
        reverse_faces(mesh, flipped);
        const RepairResult r = repaired(mesh);
        expect_report(r.report, only({{&RepairReport::flipped, 3}}, 1));
        expect_same_surface(r.mesh, cube());
    }
}

TEST(Repair, TurnsAnInsideOutCubeOutward) {
    PolygonMesh mesh = cube();
    reverse_faces(mesh, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
    ASSERT_LT(signed_volume(mesh), 0);
    EXPECT_FALSE(needs_repair(mesh));  // consistent: a manifold-only algorithm would not mind
    EXPECT_EQ(audit_mesh(mesh)->inverted_components, 1u);
    const RepairResult r = repaired(mesh);
    expect_report(r.report, only({{&RepairReport::flipped, 12}}, 1));
    EXPECT_NEAR(signed_volume(r.mesh), 1.0, 1e-12);
    expect_same_surface(r.mesh, cube());
}

TEST(Repair, DropsDuplicateFacesInEitherWinding) {
    for (const bool back_to_back : {false, true}) {
        PolygonMesh mesh = cube();
        std::vector<Index> copy(mesh.face(3).begin(), mesh.face(3).end());
        if (back_to_back) std::reverse(copy.begin(), copy.end());
        mesh.add_face(copy);
        EXPECT_TRUE(needs_repair(mesh));
        const RepairResult r = repaired(mesh);
        expect_report(r.report, only({{&RepairReport::duplicate, 1}}, 1));
        EXPECT_EQ(r.mesh.face_indices, cube().face_indices);  // the first of the two stays
    }
}

TEST(Repair, CutsAFinApart) {
    PolygonMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0.2}, {0.5, 0.3, 1}};
    mesh.add_face({0, 1, 2});
    mesh.add_face({1, 0, 3});
    mesh.add_face({0, 1, 4});  // a third face on edge 0-1
    EXPECT_EQ(audit_mesh(mesh)->nonmanifold_edges, 1u);
    const RepairResult r = repaired(mesh);
    // the first two faces stay joined; the third gets its own copies of vertices 0 and 1
    expect_report(r.report, only({{&RepairReport::nonmanifold_split, 2}}, 2));
    EXPECT_EQ(edge_stats(r.mesh).edges, 5u + 3u);
    EXPECT_EQ(r.mesh.face(2)[0], 5u);
    EXPECT_EQ(r.mesh.face(2)[1], 6u);
    EXPECT_EQ(r.mesh.positions[5], mesh.positions[0]);
    EXPECT_EQ(r.mesh.positions[6], mesh.positions[1]);
}

TEST(Repair, FinOfFacesInOneDirectionPairsTwoOfThem) {
    PolygonMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0.2}, {0.5, 0.3, 1}};
    mesh.add_face({0, 1, 2});
    mesh.add_face({0, 1, 3});
    mesh.add_face({0, 1, 4});
    const RepairResult r = repaired(mesh);
    expect_report(r.report, only({{&RepairReport::flipped, 1}, {&RepairReport::nonmanifold_split, 2}}, 2));
    // without orientation no two of them can be joined: each keeps its winding and its own edge
    RepairOptions keep_winding;
    keep_winding.orient = false;
    const RepairResult kept = repaired(mesh, keep_winding);
    expect_report(kept.report, only({{&RepairReport::nonmanifold_split, 4}}, 3));
}

TEST(Repair, OpenSeamsAreCoincidentVerticesOnBoundaryEdges) {
    EXPECT_EQ(count_open_seam_vertices(cube()), 0u);
    // a soup of the cube: 36 corners at 8 positions, all on boundary edges
    EXPECT_EQ(count_open_seam_vertices(soup(cube())), 36u - 8u);
    // flat-shaded quads: 24 corners at 8 positions
    EXPECT_EQ(count_open_seam_vertices(soup(shapes::cube())), 24u - 8u);
    // two closed cubes at the same place: coincident vertices, but no boundary edge
    PolygonMesh twice = cube();
    append(twice, cube());
    EXPECT_EQ(count_open_seam_vertices(twice), 0u);
    // one face cut off along two edges (its own copies of its three corners): three seam vertices; a fourth copy of a
    // corner that is on no boundary edge does not count
    PolygonMesh cut = cube();
    const auto f = cut.face(0);
    const std::array<Index, 3> corners{f[0], f[1], f[2]};
    for (int j = 0; j < 3; ++j) {
        cut.face_indices[cut.face_offsets[0] + j] = static_cast<Index>(cut.positions.size());
        cut.positions.push_back(cut.positions[corners[j]]);
    }
    EXPECT_EQ(count_open_seam_vertices(cut), 3u);
    cut.positions.push_back(cut.positions[corners[0]]);
    EXPECT_EQ(count_open_seam_vertices(cut), 3u);
}

TEST(Repair, SplitsABowTie) {
    PolygonMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
    mesh.add_face({0, 1, 2});
    mesh.add_face({0, 3, 4});
    EXPECT_TRUE(needs_repair(mesh));
    EXPECT_EQ(audit_mesh(mesh)->nonmanifold_vertices, 1u);
    const RepairResult r = repaired(mesh);
    expect_report(r.report, only({{&RepairReport::nonmanifold_split, 1}}, 2));
    EXPECT_EQ(r.mesh.face(1)[0], 5u);
}

TEST(Repair, SeparatesTwoCubesThatShareOneVertex) {
    PolygonMesh mesh = cube();
    append(mesh, cube(), {1, 1, 1});  // its corner (-0.5, -0.5, -0.5) lands on the first cube's (0.5, 0.5, 0.5)
    const RepairResult r = repaired(mesh);
    expect_report(r.report, only({{&RepairReport::welded, 1}, {&RepairReport::nonmanifold_split, 1}}, 2));
    const std::vector<double> volumes = closed_component_volumes(r.mesh, faces_by_edge(r.mesh));
    ASSERT_EQ(volumes.size(), 2u);
    for (double v : volumes) EXPECT_NEAR(v, 1.0, 1e-12);
}

TEST(Repair, DropsDegenerateFaces) {
    PolygonMesh mesh = cube();
    mesh.positions.push_back({2, 0, 0});
    mesh.positions.push_back({3, 1, 1});
    mesh.positions.push_back({5, 3, 3});  // on the line through the previous two
    mesh.add_face({0, 1, 1});
    mesh.add_face({8, 9, 10});
    mesh.add_face({2, 9, 2, 3});
    const RepairResult r = repaired(mesh);
    expect_report(r.report, only({{&RepairReport::degenerate, 3}, {&RepairReport::unreferenced, 3}}, 1));
    EXPECT_EQ(r.mesh.face_indices, cube().face_indices);
    EXPECT_EQ(r.mesh.positions.size(), 8u);
}

PolygonMesh sphere() {
    SubdivisionOptions options;
    options.scheme = SubdivisionScheme::Loop;
    options.levels = 2;
    auto refined = subdivide(shapes::icosahedron(), options);
    EXPECT_TRUE(refined.ok());
    return *refined;
}

TEST(Repair, FillsASmallHoleInASphere) {
    const PolygonMesh closed = sphere();
    ASSERT_TRUE(is_watertight(closed));
    // remove every face around vertex 0: a hole of as many edges as the vertex has faces (5 or 6)
    PolygonMesh holed;
    holed.positions = closed.positions;
    std::size_t removed = 0;
    for (std::size_t f = 0; f < closed.face_count(); ++f) {
        const auto face = closed.face(f);
        if (std::find(face.begin(), face.end(), 0u) != face.end()) {
            ++removed;
            continue;
        }
        holed.add_face(face);
    }
    ASSERT_GE(removed, 5u);
    ASSERT_EQ(testing::boundary_loop_count(holed), 1u);
    RepairOptions options;
    options.max_hole_edges = removed;
    const RepairResult r = repaired(holed, options);
    expect_report(r.report, only({{&RepairReport::holes_filled, 1},
                                  {&RepairReport::fill_faces, removed - 2},
                                  {&RepairReport::unreferenced, 1}},
                                 1));
    EXPECT_TRUE(is_watertight(r.mesh));
    EXPECT_GT(signed_volume(r.mesh), 0);
    // a hole larger than max_hole_edges stays open, uncounted
    options.max_hole_edges = removed - 1;
    const RepairResult open = repaired(holed, options);
    EXPECT_EQ(open.report.holes_filled, 0u);
    EXPECT_EQ(testing::boundary_loop_count(open.mesh), 1u);
}

TEST(Repair, FillsTheHoleOfAnInsideOutOpenBoxOutward) {
    PolygonMesh mesh = cube();
    mesh.face_offsets.resize(11);  // drop the last two triangles: one square hole
    mesh.face_indices.resize(30);
    reverse_faces(mesh, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9});
    RepairOptions options;
    options.max_hole_edges = 4;
    const RepairResult r = repaired(mesh, options);
    expect_report(
        r.report,
        only({{&RepairReport::flipped, 10}, {&RepairReport::holes_filled, 1}, {&RepairReport::fill_faces, 2}}, 1));
    EXPECT_TRUE(is_watertight(r.mesh));
    EXPECT_NEAR(signed_volume(r.mesh), 1.0, 1e-12);
}

TEST(Repair, DropsSmallComponents) {
    PolygonMesh mesh = cube();
    PolygonMesh triangle;
    triangle.positions = {{3, 0, 0}, {4, 0, 0}, {3, 1, 0}};
    triangle.add_face({0, 1, 2});
    append(mesh, triangle);
    append(mesh, shapes::grid(1, 1, true), {5, 0, 0});  // two triangles
    RepairOptions options;
    options.min_component_faces = 3;
    const RepairResult r = repaired(mesh, options);
    expect_report(r.report, only({{&RepairReport::small_components, 2},
                                  {&RepairReport::removed_faces, 3},
                                  {&RepairReport::unreferenced, 7}},
                                 1));
    EXPECT_EQ(r.mesh.face_indices, cube().face_indices);
    const RepairResult kept = repaired(mesh);
    EXPECT_EQ(kept.report.components, 3u);
    EXPECT_FALSE(kept.report.changed());
}

TEST(Repair, AMeshThatNeedsNothingComesBackBitForBit) {
    PolygonMesh tagged = cube();
    tagged.normals = compute_vertex_normals(tagged);
    tagged.tags.creases.push_back({0, 1, 2.5});
    tagged.tags.corners.push_back({3, 1.0});
    for (const PolygonMesh& mesh : {tagged, shapes::torus(8, 6), shapes::mixed_polygons(), shapes::grid(3, 2)}) {
        EXPECT_FALSE(needs_repair(mesh));
        const RepairResult r = repaired(mesh);
        EXPECT_FALSE(r.report.changed());
        expect_report(r.report, only({}, 1));
        EXPECT_EQ(r.mesh.positions.size(), mesh.positions.size());
        EXPECT_EQ(0, std::memcmp(r.mesh.positions.data(), mesh.positions.data(), mesh.positions.size() * sizeof(Vec3)));
        EXPECT_EQ(r.mesh.face_offsets, mesh.face_offsets);
        EXPECT_EQ(r.mesh.face_indices, mesh.face_indices);
        EXPECT_EQ(r.mesh.normals.size(), mesh.normals.size());
        EXPECT_EQ(r.mesh.tags.creases.size(), mesh.tags.creases.size());
        EXPECT_EQ(r.mesh.tags.corners.size(), mesh.tags.corners.size());
    }
}

TEST(Repair, UvsFollowTheirCornersAndTagsTheirVertices) {
    PolygonMesh mesh = soup(cube());
    for (std::size_t i = 0; i < mesh.face_indices.size(); ++i) {
        mesh.uvs.push_back({static_cast<double>(i), 0.5});
        mesh.uv_indices.push_back(static_cast<Index>(i));
    }
    reverse_faces(mesh, {4});
    std::reverse(mesh.uv_indices.begin() + 12, mesh.uv_indices.begin() + 15);
    mesh.tags.creases.push_back({3, 4, 1.0});  // vertices welded into others: remapped
    mesh.tags.creases.push_back({0, 3, 1.0});  // both ends weld into vertex 0: dropped
    mesh.tags.holes.push_back(5);
    const RepairResult r = repaired(mesh);
    EXPECT_EQ(r.report.flipped, 1u);
    // every (position, uv) corner of the output is a corner of the input
    std::set<std::pair<std::array<double, 3>, double>> corners;
    for (std::size_t c = 0; c < mesh.face_indices.size(); ++c) {
        const Vec3& p = mesh.positions[mesh.face_indices[c]];
        corners.insert({{p.x, p.y, p.z}, mesh.uvs[mesh.uv_indices[c]].x});
    }
    ASSERT_EQ(r.mesh.uv_indices.size(), r.mesh.face_indices.size());
    for (std::size_t c = 0; c < r.mesh.face_indices.size(); ++c) {
        const Vec3& p = r.mesh.positions[r.mesh.face_indices[c]];
        EXPECT_TRUE(corners.count({{p.x, p.y, p.z}, r.mesh.uvs[r.mesh.uv_indices[c]].x})) << "corner " << c;
    }
    ASSERT_EQ(r.mesh.tags.creases.size(), 1u);
    EXPECT_EQ(r.mesh.positions[r.mesh.tags.creases[0].v0], mesh.positions[3]);
    EXPECT_EQ(r.mesh.positions[r.mesh.tags.creases[0].v1], mesh.positions[4]);
    EXPECT_EQ(r.mesh.tags.holes, std::vector<Index>{5});
}

TEST(Repair, WeldsWithinATolerance) {
    PolygonMesh mesh = soup(cube());
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-1e-4, 1e-4);
    for (Vec3& p : mesh.positions) p += Vec3{jitter(rng), jitter(rng), jitter(rng)};
    EXPECT_EQ(repaired(mesh).report.welded, 0u);
    RepairOptions options;
    options.weld_tolerance = 1e-3;
    const RepairResult r = repaired(mesh, options);
    EXPECT_EQ(r.report.welded, 28u);
    EXPECT_TRUE(is_watertight(r.mesh));
}

TEST(Repair, RejectsBadOptionsAndStopsWhenCancelled) {
    RepairOptions options;
    options.weld_tolerance = -1;
    EXPECT_EQ(repair_mesh(cube(), options).error().code, ErrorCode::InvalidArgument);
    options.weld_tolerance = std::nan("");
    EXPECT_EQ(repair_mesh(cube(), options).error().code, ErrorCode::InvalidArgument);
    PolygonMesh bad = cube();
    bad.face_indices[0] = 99;
    EXPECT_EQ(repair_mesh(bad).error().code, ErrorCode::IndexOutOfRange);
    EXPECT_TRUE(needs_repair(bad));
    std::atomic<bool> stop{true};
    RepairOptions cancelled;
    cancelled.cancel.flag = &stop;
    EXPECT_EQ(repair_mesh(cube(), cancelled).error().code, ErrorCode::Cancelled);
}

// ---- property: random soups ----

//! `faces` random triangles over `vertices` random points (indices may repeat); a third of the faces get their own
//! copies of the points, so that welding has work to do.
PolygonMesh random_soup(std::mt19937& rng, int vertices, int faces) {
    PolygonMesh mesh;
    std::uniform_real_distribution<double> coord(-1, 1);
    for (int i = 0; i < vertices; ++i) mesh.positions.push_back({coord(rng), coord(rng), coord(rng)});
    std::uniform_int_distribution<int> pick(0, vertices - 1);
    for (int f = 0; f < faces; ++f) {
        std::array<Index, 3> face{};
        for (Index& v : face) {
            v = static_cast<Index>(pick(rng));
            if (f % 3 == 0) {
                mesh.positions.push_back(mesh.positions[v]);
                v = static_cast<Index>(mesh.positions.size() - 1);
            }
        }
        mesh.add_face(face);
    }
    return mesh;
}

TEST(Repair, RandomSoupsAlwaysComeOutManifold) {
    for (unsigned seed = 0; seed < 2000; ++seed) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        std::mt19937 rng(seed);
        const int vertices = 4 + static_cast<int>(seed % 9);
        const PolygonMesh mesh = random_soup(rng, vertices, 3 + static_cast<int>(rng() % 40));
        RepairOptions options;
        options.orient = seed % 4 != 3;
        options.weld_tolerance = seed % 5 == 4 ? 0.3 : 0.0;
        options.max_hole_edges = seed % 2 ? 6 : 0;
        options.min_component_faces = seed % 7 == 6 ? 2 : 0;
        const RepairResult r = repaired(mesh, options);
        if (::testing::Test::HasFailure()) break;
        // repairing the output again welds the copies of split vertices (and joins and splits them again, not always
        // the same way once small components are gone), but finds no degenerate or duplicate face
        const RepairResult again = repaired(r.mesh, options);
        EXPECT_EQ(again.report.degenerate, 0u);
        EXPECT_EQ(again.report.duplicate, 0u);
    }
}

// check_manifold: the rule /simplify and /remesh apply with repair "none"; the defect is named and located at a face.
TEST(CheckManifold, AcceptsManifoldMeshesWithOrWithoutBoundary) {
    for (const PolygonMesh& mesh : {shapes::cube(), shapes::torus(12, 6), shapes::icosahedron(), shapes::grid(4, 3),
                                    shapes::grid_with_holes(), shapes::mixed_polygons()}) {
        const Status manifold = check_manifold(mesh);
        EXPECT_TRUE(manifold.ok()) << manifold.error().message;
    }
}

TEST(CheckManifold, NamesTheDefectAndAFaceAtIt) {
    const auto error_of = [](std::vector<Vec3> positions, std::vector<std::vector<Index>> faces) {
        PolygonMesh m;
        m.positions = std::move(positions);
        for (const auto& f : faces) m.add_face(f);
        const Status status = check_manifold(m);
        EXPECT_FALSE(status.ok());
        return status.ok() ? GeoError{} : status.error();
    };
    const std::vector<Vec3> five = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    // a fin: the third face on (0, 1)
    GeoError e = error_of(five, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
    EXPECT_EQ(e.code, ErrorCode::NonManifold);
    EXPECT_EQ(e.element_kind, ElementKind::Face);
    EXPECT_EQ(e.element, 2);
    EXPECT_EQ(e.message, "edge (0, 1) is shared by more than two faces (face 2 is one)");
    // the same direction twice: the second face
    e = error_of(five, {{0, 1, 2}, {0, 1, 3}});
    EXPECT_EQ(e.element, 1);
    EXPECT_EQ(e.message,
              "edge (0, 1) is traversed in the same direction by face 1 and another face (inconsistent orientation or "
              "a duplicate face)");
    // of two defective edges, the one whose offending face comes first
    e = error_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}},
                 {{5, 6, 7}, {5, 6, 7}, {0, 1, 2}, {0, 1, 3}});
    EXPECT_EQ(e.element, 1);
    // a bow-tie: two triangles meeting at vertex 2, located at the first face that uses it
    e = error_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 0}, {2, 2, 0}}, {{0, 1, 2}, {2, 3, 4}});
    EXPECT_EQ(e.element, 0);
    EXPECT_EQ(e.message, "vertex 2 joins several fans of faces (a non-manifold vertex; face 0 uses it)");
    // polygons: quads meeting at a corner
    e = error_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}},
                 {{0, 1, 2, 3}, {2, 4, 5, 6}});
    EXPECT_EQ(e.message, "vertex 2 joins several fans of faces (a non-manifold vertex; face 0 uses it)");
    // what repair_mesh makes of them passes
    PolygonMesh bowtie;
    bowtie.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 0}, {2, 2, 0}};
    bowtie.add_face({0, 1, 2});
    bowtie.add_face({2, 3, 4});
    auto repaired = repair_mesh(bowtie);
    ASSERT_TRUE(repaired.ok());
    EXPECT_EQ(repaired->report.nonmanifold_split, 1u);
    EXPECT_TRUE(check_manifold(repaired->mesh).ok());
}

}  // namespace
}  // namespace surfaced
