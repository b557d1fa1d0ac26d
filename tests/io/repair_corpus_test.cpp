// The repair corpus (tests/data/repair-corpus, written by its generate.py): every file is read the way the service
// reads an upload to /repair, /simplify and /remesh (read_mesh, faces that repeat a vertex allowed), repaired with the
// default options, and checked against expected.json: each count of the report, the input and output sizes, the
// guarantees of geometry/repair/repair.h on the output, and, where the repair only re-indexes, the same surface as the
// file's own triangles (exact position triples: Hausdorff distance 0). The glTF scene's world positions are checked
// against the node transforms worked out by hand. Every file needs an entry and every entry a file.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/io/mesh_io.h"
#include "geometry/repair/repair.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/repair_asserts.h"

namespace surfaced {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using testing::FaceCorners;
using testing::surface_faces;

const fs::path kCorpus = fs::path(SURFACED_TEST_DATA_DIR) / "repair-corpus";
//! Files in the corpus directory that are not corpus cases.
const std::set<std::string> kNotCases = {"generate.py", "expected.json"};

std::vector<std::string> corpus_files() {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(kCorpus))
        if (entry.is_regular_file() && !kNotCases.count(entry.path().filename().string()))
            names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

Json manifest() {
    const std::string text = testing::read_file((kCorpus / "expected.json").string());
    Json json = Json::parse(text, nullptr, false);
    EXPECT_FALSE(json.is_discarded()) << "expected.json is not valid JSON";
    return json.is_discarded() ? Json::object() : json.value("files", Json::object());
}

//! As api/operations/request_forms.cpp reads an upload for an operation that repairs its input.
Result<PolygonMesh> read_like_the_service(const std::string& name, ReadReport* report) {
    const auto format = format_from_extension(name);
    if (!format) return make_error(ErrorCode::Unsupported, "no mesh format for " + name);
    ReadOptions options;
    options.allow_repeated_vertices = true;
    return read_mesh(testing::read_file((kCorpus / name).string()), *format, options, report);
}

//! The triangles of an STL file as the file stores them, each with its own three corners (binary by the size rule,
//! else ascii `vertex` lines): parsed here, independently of the reader, which welds.
PolygonMesh stl_triangles(const std::string& bytes) {
    PolygonMesh soup;
    std::vector<Vec3> corners;
    std::uint32_t count = 0;
    if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, 4);
    if (bytes.size() >= 84 && bytes.size() == 84 + 50 * std::size_t{count}) {
        for (std::uint32_t t = 0; t < count; ++t)
            for (int c = 0; c < 3; ++c) {
                float xyz[3];
                std::memcpy(xyz, bytes.data() + 84 + 50 * std::size_t{t} + 12 + 12 * c, sizeof xyz);
                corners.push_back({xyz[0], xyz[1], xyz[2]});
            }
    } else {
        std::istringstream in(bytes);
        std::string word;
        while (in >> word)
            if (word == "vertex") {
                Vec3 p;
                in >> p.x >> p.y >> p.z;
                corners.push_back(p);
            }
    }
    for (std::size_t i = 0; i + 2 < corners.size(); i += 3) {
        const auto base = static_cast<Index>(soup.positions.size());
        soup.positions.insert(soup.positions.end(), corners.begin() + static_cast<std::ptrdiff_t>(i),
                              corners.begin() + static_cast<std::ptrdiff_t>(i + 3));
        soup.add_face({base, base + 1, base + 2});
    }
    return soup;
}

//! The RepairReport counts by their names in expected.json.
const std::pair<const char*, std::size_t RepairReport::*> kCounts[] = {
    {"welded", &RepairReport::welded},
    {"degenerate", &RepairReport::degenerate},
    {"duplicate", &RepairReport::duplicate},
    {"flipped", &RepairReport::flipped},
    {"nonmanifold_split", &RepairReport::nonmanifold_split},
    {"small_components", &RepairReport::small_components},
    {"removed_faces", &RepairReport::removed_faces},
    {"holes_filled", &RepairReport::holes_filled},
    {"fill_faces", &RepairReport::fill_faces},
    {"unreferenced", &RepairReport::unreferenced},
    {"components", &RepairReport::components},
};

std::string report_text(const RepairReport& report) {
    std::string out;
    for (const auto& [name, field] : kCounts)
        out += std::string(out.empty() ? "" : ", ") + name + "=" + std::to_string(report.*field);
    return out;
}

TEST(RepairCorpus, EveryFileHasAnEntryAndEveryEntryAFile) {
    const Json files = manifest();
    const std::vector<std::string> names = corpus_files();
    EXPECT_GE(names.size(), 12u);
    for (const std::string& name : names) EXPECT_TRUE(files.contains(name)) << name << " has no entry in expected.json";
    for (const auto& [name, entry] : files.items())
        EXPECT_TRUE(std::binary_search(names.begin(), names.end(), name))
            << "expected.json lists missing file " << name;
}

TEST(RepairCorpus, EachFileRepairsToItsExpectedCounts) {
    const Json files = manifest();
    for (const std::string& name : corpus_files()) {
        SCOPED_TRACE(name);
        if (!files.contains(name)) continue;  // reported by EveryFileHasAnEntryAndEveryEntryAFile
        const Json& want = files[name];
        ReadReport read_report;
        auto read = read_like_the_service(name, &read_report);
        if (want.contains("read_error")) {
            ASSERT_FALSE(read.ok()) << "read " << read->vertex_count() << " vertices, " << read->face_count()
                                    << " faces";
            EXPECT_NE(read.error().message.find(want["read_error"].get<std::string>()), std::string::npos)
                << read.error().message;
            continue;
        }
        ASSERT_TRUE(read.ok()) << read.error().message;
        const PolygonMesh& input = read.value();
        EXPECT_EQ(input.vertex_count(), want.at("input").at("vertices").get<std::size_t>());
        EXPECT_EQ(input.face_count(), want.at("input").at("faces").get<std::size_t>());
        EXPECT_EQ(read_report.skipped_primitives, want.at("input").value("skipped_primitives", std::size_t{0}));

        auto repaired = repair_mesh(input);
        ASSERT_TRUE(repaired.ok()) << repaired.error().message;
        const RepairResult& r = repaired.value();
        const Json& counts = want.at("repairs");
        ASSERT_EQ(counts.size(), std::size(kCounts)) << "every RepairReport count, no other key";
        for (const auto& [key, field] : kCounts)
            EXPECT_EQ(r.report.*field, counts.at(key).get<std::size_t>())
                << key << " (got " << report_text(r.report) << ")";
        EXPECT_EQ(r.mesh.vertex_count(), want.at("output").at("vertices").get<std::size_t>());
        EXPECT_EQ(r.mesh.face_count(), want.at("output").at("faces").get<std::size_t>());
        testing::expect_repaired(r.mesh);
        testing::expect_counts_add_up(input, r);

        // The same surface where nothing had to go: compared with the file's own triangles (an STL file's, before
        // the reader welds them) as exact position triples.
        const std::string surface = want.at("surface").get<std::string>();
        const bool stl = format_from_extension(name) == MeshFormat::Stl;
        const PolygonMesh as_stored = stl ? stl_triangles(testing::read_file((kCorpus / name).string())) : input;
        if (surface == "unchanged") {
            EXPECT_FALSE(r.report.changed());
            ASSERT_EQ(r.mesh.positions.size(), input.positions.size());
            EXPECT_EQ(
                0, std::memcmp(r.mesh.positions.data(), input.positions.data(), input.positions.size() * sizeof(Vec3)));
            EXPECT_EQ(r.mesh.face_offsets, input.face_offsets);
            EXPECT_EQ(r.mesh.face_indices, input.face_indices);
        }
        if (surface == "unchanged" || surface == "same") {
            EXPECT_EQ(surface_faces(r.mesh), surface_faces(as_stored));
        } else if (surface == "same_unoriented") {
            EXPECT_EQ(surface_faces(r.mesh, true), surface_faces(as_stored, true));
            EXPECT_TRUE(surface_faces(r.mesh) != surface_faces(as_stored)) << "some face should have been reversed";
        } else {
            EXPECT_EQ(surface, "changed") << "surface is one of unchanged, same, same_unoriented, changed";
        }
    }
}

// nested_transforms.gltf: node 1 (translation (0, 0, 1), scale (1, 1, 3), the mesh) under node 0 (translation
// (10, 0, 0), 90 degrees about +z, scale 2) puts a local (x, y, z) at (10 - 2y, 2x, 6z + 2).
TEST(RepairCorpus, GltfNodeTransformsGiveTheWorldPositionsWorkedOutByHand) {
    const std::array<std::array<double, 3>, 8> local = {
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
    const std::array<std::array<Index, 3>, 12> triangles = {{{0, 3, 2},
                                                             {0, 2, 1},
                                                             {4, 5, 6},
                                                             {4, 6, 7},
                                                             {0, 1, 5},
                                                             {0, 5, 4},
                                                             {1, 2, 6},
                                                             {1, 6, 5},
                                                             {2, 3, 7},
                                                             {2, 7, 6},
                                                             {3, 0, 4},
                                                             {3, 4, 7}}};
    std::vector<Vec3> world;
    for (const auto& [x, y, z] : local) world.push_back({10 - 2 * y, 2 * x, 6 * z + 2});

    ReadReport read_report;
    auto read = read_like_the_service("nested_transforms.gltf", &read_report);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read_report.skipped_primitives, 1u);  // the POINTS primitive
    const PolygonMesh& mesh = read.value();
    ASSERT_EQ(mesh.vertex_count(), 8u);  // the two triangle primitives' vertices welded, no point read
    // each vertex is one of the hand-computed positions (the 90 degree quaternion is not exact in binary: 1e-12)
    std::vector<Index> which(mesh.vertex_count());
    std::set<Index> seen;
    for (Index v = 0; v < mesh.vertex_count(); ++v) {
        const auto nearest = std::min_element(world.begin(), world.end(), [&](const Vec3& a, const Vec3& b) {
            return norm(a - mesh.positions[v]) < norm(b - mesh.positions[v]);
        });
        EXPECT_LT(norm(*nearest - mesh.positions[v]), 1e-12) << "vertex " << v << " at " << mesh.positions[v].x << " "
                                                             << mesh.positions[v].y << " " << mesh.positions[v].z;
        which[v] = static_cast<Index>(nearest - world.begin());
        seen.insert(which[v]);
    }
    EXPECT_EQ(seen.size(), 8u);
    // the faces are the cube's, with its winding (the transforms do not mirror), and it encloses 2 * 2 * 2 * 3
    std::set<std::vector<Index>> want, got;
    const auto rotated = [](std::vector<Index> f) {
        std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
        return f;
    };
    for (const auto& t : triangles) want.insert(rotated({t[0], t[1], t[2]}));
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        std::vector<Index> face;
        for (Index v : mesh.face(f)) face.push_back(which[v]);
        got.insert(rotated(face));
    }
    EXPECT_EQ(got, want);
    EXPECT_NEAR(testing::signed_volume(mesh), 24.0, 1e-9);
}

}  // namespace
}  // namespace surfaced
