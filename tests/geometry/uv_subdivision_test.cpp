// Face-varying texture coordinates against OpenSubdiv's InterpolateFaceVarying, every interpolation mode, on every
// regression shape that has UVs (and on built-in shapes with seams): per face corner, within 1e-9.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/subdivide.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/osd_reference.h"

namespace surfaced {
namespace {

namespace fs = std::filesystem;

constexpr UvInterpolation kModes[] = {UvInterpolation::None,         UvInterpolation::CornersOnly,
                                      UvInterpolation::CornersPlus1, UvInterpolation::CornersPlus2,
                                      UvInterpolation::Boundaries,   UvInterpolation::All};
const char* mode_name(UvInterpolation m) {
    switch (m) {
        case UvInterpolation::None: return "none";
        case UvInterpolation::CornersOnly: return "corners-only";
        case UvInterpolation::CornersPlus1: return "corners-plus1";
        case UvInterpolation::CornersPlus2: return "corners-plus2";
        case UvInterpolation::Boundaries: return "boundaries";
        case UvInterpolation::All: return "all";
    }
    return "?";
}

// Largest per-corner UV difference, or a huge value when the layouts differ in size.
double uv_deviation(const PolygonMesh& ours, const PolygonMesh& ref) {
    if (ours.uv_indices.size() != ref.uv_indices.size() || !ours.has_uvs()) return 1e300;
    double worst = 0;
    for (std::size_t i = 0; i < ref.uv_indices.size(); ++i) {
        const Vec2 a = ours.uvs[ours.uv_indices[i]], b = ref.uvs[ref.uv_indices[i]];
        worst = std::max({worst, std::abs(a.x - b.x), std::abs(a.y - b.y)});
    }
    return worst;
}

// A cube with a UV seam layout (a cross-shaped unwrap: corners and seams of every kind).
PolygonMesh seamed_cube() {
    PolygonMesh m = shapes::cube();
    // each face gets its own square in a 3x2 atlas: every edge is a seam, every vertex a junction of 3 regions
    for (std::size_t f = 0; f < m.face_count(); ++f) {
        const double u0 = double(f % 3) / 3.0, v0 = double(f / 3) / 2.0;
        const Vec2 square[4] = {{u0, v0}, {u0 + 1.0 / 3, v0}, {u0 + 1.0 / 3, v0 + 0.5}, {u0, v0 + 0.5}};
        for (int k = 0; k < 4; ++k) {
            m.uv_indices.push_back(static_cast<Index>(m.uvs.size()));
            m.uvs.push_back(square[k]);
        }
    }
    return m;
}

// A grid whose left and right halves are separate UV charts (one straight seam, boundary corners, T-junctions).
PolygonMesh seamed_grid() {
    PolygonMesh m = shapes::grid(4, 3);
    for (std::size_t f = 0; f < m.face_count(); ++f)
        for (Index v : m.face(f)) {
            const Vec3& p = m.positions[v];
            const bool right = (f % 4) >= 2;
            m.uv_indices.push_back(static_cast<Index>(m.uvs.size()));
            m.uvs.push_back({p.x * 0.8 + (right ? 0.15 : 0.0), p.y * 0.9 + p.x * p.x * 0.1});
        }
    return m;
}

TEST(UvSubdivision, BuiltInSeamedShapesMatchOpenSubdiv) {
    const std::pair<const char*, PolygonMesh> meshes[] = {{"seamed_cube", seamed_cube()},
                                                          {"seamed_grid", seamed_grid()}};
    for (const auto& [name, mesh] : meshes)
        for (UvInterpolation mode : kModes)
            for (int levels = 1; levels <= 3; ++levels) {
                SubdivisionOptions options;
                options.levels = levels;
                options.uv_interpolation = mode;
                auto ours = subdivide(mesh, options);
                ASSERT_TRUE(ours.ok()) << ours.error().message;
                const PolygonMesh ref = testing::osd_subdivide(mesh, options);
                EXPECT_LE(uv_deviation(*ours, ref), 1e-9) << name << " " << mode_name(mode) << " level " << levels;
                EXPECT_TRUE(validate(*ours).ok());
            }
}

TEST(UvSubdivision, CornersStayPutWhereTheModeKeepsThem) {
    // every face of the seamed cube is its own UV chart, so every UV value is a one-face corner: with any mode but
    // "none" the children of the original corners keep their UVs exactly, at every level
    const PolygonMesh mesh = seamed_cube();
    for (UvInterpolation mode : kModes) {
        if (mode == UvInterpolation::None) continue;
        SubdivisionOptions options;
        options.levels = 2;
        options.uv_interpolation = mode;
        auto out = subdivide(mesh, options);
        ASSERT_TRUE(out.ok());
        // corner k of face f (level 0) is corner k of the first child of the first child of f (quads keep their
        // parametric orientation in OpenSubdiv's numbering: child j of a quad has the parent's corner j at j)
        for (std::size_t f = 0; f < mesh.face_count(); ++f)
            for (std::size_t k = 0; k < 4; ++k) {
                const std::size_t child = (f * 4 + k) * 4 + k;  // level-2 face: child k of child k of face f
                const Vec2 got = out->uvs[out->uv_indices[child * 4 + k]];
                const Vec2 want = mesh.uvs[mesh.uv_indices[f * 4 + k]];
                EXPECT_EQ(got.x, want.x) << mode_name(mode);
                EXPECT_EQ(got.y, want.y) << mode_name(mode);
            }
    }
}

// The same two charts with shared UV indices inside each chart: the seam vertices have two values each.
PolygonMesh two_chart_grid() {
    PolygonMesh m = shapes::grid(4, 3);
    std::vector<Index> ids(2 * m.positions.size(), kInvalidIndex);
    for (std::size_t f = 0; f < m.face_count(); ++f)
        for (Index v : m.face(f)) {
            const bool right = (f % 4) >= 2;
            Index& id = ids[2 * v + right];
            if (id == kInvalidIndex) {
                const Vec3& p = m.positions[v];
                id = static_cast<Index>(m.uvs.size());
                // curved along the seam too, so that corner and crease rules differ there
                m.uvs.push_back({p.x * 0.8 + (right ? 0.15 : 0.0) + p.y * p.y * 0.2, p.y * 0.9 + p.x * p.x * 0.1});
            }
            m.uv_indices.push_back(id);
        }
    return m;
}

TEST(UvSubdivision, DependentSharpValueDecaysWithItsSibling) {
    // the seam vertex (2, 1) has two values; a semi-sharp crease inside the left one's span makes
    // OpenSubdiv keep the right one a corner too (corners-plus1/2, "dependent-sharp") until the crease decays, then
    // blend it into a crease with the left one's fractional weight: sharpness below, at and past the levels
    for (const double sharpness : {0.5, 1.0, 1.5, 2.7})
        for (const CreaseMethod method : {CreaseMethod::Uniform, CreaseMethod::Chaikin}) {
            PolygonMesh mesh = two_chart_grid();
            mesh.tags.creases.push_back({6, 7, sharpness});
            mesh.tags.creases.push_back({11, 12, sharpness * 0.5});  // and a second seam vertex, other sharpness
            for (UvInterpolation mode : kModes)
                for (int levels = 1; levels <= 3; ++levels) {
                    SubdivisionOptions options;
                    options.levels = levels;
                    options.uv_interpolation = mode;
                    options.crease_method = method;
                    auto ours = subdivide(mesh, options);
                    ASSERT_TRUE(ours.ok()) << ours.error().message;
                    const PolygonMesh ref = testing::osd_subdivide(mesh, options);
                    EXPECT_LE(uv_deviation(*ours, ref), 1e-9)
                        << "sharpness " << sharpness << " " << mode_name(mode) << " level " << levels;
                }
        }
}

TEST(UvSubdivision, RegressionShapesWithUvsMatchOpenSubdiv) {
    const fs::path dir = fs::path(SURFACED_TEST_DATA_DIR) / "opensubdiv-shapes";
    int checked = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().stem().string();
        if (entry.path().extension() != ".obj" || name.rfind("bilinear", 0) == 0) continue;
        ReadOptions read_options;
        read_options.allow_repeated_vertices = true;  // as OpenSubdiv reads the corpus (the *_nonman_edges shapes)
        auto mesh = read_obj(testing::read_file(entry.path().string()), read_options);
        ASSERT_TRUE(mesh.ok()) << name << ": " << mesh.error().message;
        if (!mesh->has_uvs()) continue;
        for (UvInterpolation mode : kModes)
            for (int levels = 1; levels <= 2; ++levels) {
                SubdivisionOptions options;
                options.scheme =
                    name.rfind("loop_", 0) == 0 ? SubdivisionScheme::Loop : SubdivisionScheme::CatmullClark;
                options.levels = levels;
                options.uv_interpolation = mode;
                auto ours = subdivide(*mesh, options);
                ASSERT_TRUE(ours.ok()) << name << ": " << ours.error().message;
                const PolygonMesh ref = testing::osd_subdivide(*mesh, options);
                EXPECT_LE(uv_deviation(*ours, ref), 1e-9) << name << " " << mode_name(mode) << " level " << levels;
            }
        ++checked;
    }
    EXPECT_GE(checked, 100);
}

}  // namespace
}  // namespace surfaced
