// OpenSubdiv's own regression shapes (tests/data/opensubdiv-shapes, OBJ with `t` tags): creases, corners, holes,
// boundary modes, non-manifold topology, faces that repeat a vertex. Each shape is refined by us and by OpenSubdiv Far in this binary with the
// same options; counts, faces and positions (1e-9 of the bounding-box diagonal) must agree.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include "geometry/io/mesh_io.h"
#include "geometry/subdivision/subdivide.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/osd_reference.h"

namespace surfaced {
namespace {

namespace fs = std::filesystem;

fs::path shapes_dir() { return fs::path(SURFACED_TEST_DATA_DIR) / "opensubdiv-shapes"; }

std::vector<std::string> shape_names() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(shapes_dir(), ec))
        if (entry.path().extension() == ".obj") {
            const std::string name = entry.path().stem().string();
            if (name.rfind("catmark_", 0) == 0 || name.rfind("loop_", 0) == 0) names.push_back(name);
        }
    std::sort(names.begin(), names.end());
    return names;
}

struct Case {
    std::string shape;
    CreaseMethod method;
    TriangleRule triangle_rule;
};

// readable test names in ctest's output instead of a byte dump
void PrintTo(const Case& c, std::ostream* os) { *os << c.shape; }

std::vector<Case> cases() {
    std::vector<Case> out;
    for (const std::string& name : shape_names())
        for (auto method : {CreaseMethod::Uniform, CreaseMethod::Chaikin}) {
            out.push_back({name, method, TriangleRule::Catmark});
            if (name.rfind("catmark_", 0) == 0) out.push_back({name, method, TriangleRule::Smooth});
        }
    return out;
}

// The corpus is read as OpenSubdiv reads it: faces may repeat a vertex (catmark_nonman_edges, loop_nonman_edges,
// catmark_nonman_quadpole*), which subdivide() accepts and refines as OpenSubdiv does.
Result<PolygonMesh> read_shape(const std::string& shape) {
    ReadOptions options;
    options.allow_repeated_vertices = true;
    return read_obj(testing::read_file((shapes_dir() / (shape + ".obj")).string()), options);
}

class OpenSubdivShapes : public ::testing::TestWithParam<Case> {};

TEST_P(OpenSubdivShapes, MatchFarAtLevels1To3) {
    const Case& c = GetParam();
    auto mesh = read_shape(c.shape);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    // the shape's own `t interpolateboundary` (or edge-only), then every boundary mode explicitly
    const std::optional<BoundaryInterpolation> modes[] = {std::nullopt, BoundaryInterpolation::None,
                                                          BoundaryInterpolation::EdgeOnly,
                                                          BoundaryInterpolation::EdgeAndCorner};
    for (const auto& mode : modes)
        for (int levels = 1; levels <= 3; ++levels) {
            SubdivisionOptions options;
            options.scheme = c.shape.rfind("loop_", 0) == 0 ? SubdivisionScheme::Loop : SubdivisionScheme::CatmullClark;
            options.levels = levels;
            options.crease_method = c.method;
            options.triangle_rule = c.triangle_rule;
            if (mode) {
                options.boundary = *mode;
                options.use_mesh_boundary_tag = false;
            }
            const std::string where = "level " + std::to_string(levels) + ", boundary " +
                                      (mode ? std::to_string(static_cast<int>(*mode)) : std::string("from the shape"));
            auto ours = subdivide(*mesh, options);
            ASSERT_TRUE(ours.ok()) << ours.error().message;
            const PolygonMesh ref = testing::osd_subdivide(*mesh, options);
            ASSERT_EQ(ours->vertex_count(), ref.vertex_count()) << where;
            ASSERT_EQ(ours->face_count(), ref.face_count()) << where;
            ASSERT_EQ(ours->face_indices, ref.face_indices) << where;
            const double tolerance = 1e-9 * mesh->bounds().diagonal();
            double worst = 0;
            std::size_t worst_vertex = 0;
            for (std::size_t v = 0; v < ref.vertex_count(); ++v) {
                const double d = norm(ours->positions[v] - ref.positions[v]);
                if (d > worst) {
                    worst = d;
                    worst_vertex = v;
                }
            }
            EXPECT_LE(worst, tolerance) << where << ", vertex " << worst_vertex;
        }
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    return info.param.shape + (info.param.method == CreaseMethod::Chaikin ? "_chaikin" : "_uniform") +
           (info.param.triangle_rule == TriangleRule::Smooth ? "_smoothtri" : "");
}

INSTANTIATE_TEST_SUITE_P(Corpus, OpenSubdivShapes, ::testing::ValuesIn(cases()), case_name);

TEST(OpenSubdivShapes, CorpusIsPresent) { EXPECT_GE(shape_names().size(), 118u); }

// The five shapes whose faces repeat a vertex are in the comparison above: validate() refuses them (every other
// algorithm relies on it), validate_for_subdivision() takes them, and they really do have degenerate edges.
TEST(OpenSubdivShapes, ShapesWithRepeatedVerticesAreAcceptedForSubdivisionOnly) {
    for (const char* shape : {"catmark_nonman_edges", "catmark_nonman_quadpole8", "catmark_nonman_quadpole64",
                              "catmark_nonman_quadpole360", "loop_nonman_edges"}) {
        auto mesh = read_shape(shape);
        ASSERT_TRUE(mesh.ok()) << shape << ": " << mesh.error().message;
        const Status strict = validate(*mesh);
        ASSERT_FALSE(strict.ok()) << shape;
        EXPECT_EQ(strict.error().code, ErrorCode::DegenerateFace) << shape;
        EXPECT_NE(strict.error().message.find("more than once"), std::string::npos) << shape;
        EXPECT_TRUE(validate_for_subdivision(*mesh).ok()) << shape;
        EXPECT_FALSE(read_obj(testing::read_file((shapes_dir() / (std::string(shape) + ".obj")).string())).ok())
            << shape << ": the strict reader refuses it too";
    }
}

}  // namespace
}  // namespace surfaced
