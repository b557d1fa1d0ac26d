// The UVs' limit at (face, u, v) (uv_limit.h) against OpenSubdiv's Bfr face-varying surfaces
// (RefinerSurfaceFactory::InitFaceVaryingSurface, approximation levels at their maximum) at random points, in every
// uv_interpolation mode, on OpenSubdiv's face-varying regression shapes and on meshes cut into UV regions with seams
// and junctions; and the approximated corners-plus1/2 case measured.
#include <gtest/gtest.h>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/uv_limit.h"
#include "tests/support/uv_seams.h"
#include "tests/support/opensubdiv_shapes.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/osd_reference.h"

namespace surfaced {
namespace {

namespace fs = std::filesystem;
using namespace OpenSubdiv;

constexpr int kBfrApproxLevel = 10;  // Far's maximum isolation level

//! Bfr's face-varying surface (channel 0: the UVs) of every face of one mesh.
class BfrUvReference {
public:
    BfrUvReference(const PolygonMesh& mesh, const SubdivisionOptions& options)
        : refiner_(testing::make_refiner(mesh, options)) {
        for (const Vec2& uv : mesh.uvs) values_.insert(values_.end(), {uv.x, uv.y});
        Bfr::SurfaceFactory::Options fo;
        fo.SetApproxLevelSmooth(kBfrApproxLevel);
        fo.SetApproxLevelSharp(kBfrApproxLevel);
        factory_ = std::make_unique<Bfr::RefinerSurfaceFactory<>>(*refiner_, fo);
    }
    bool valid() const { return refiner_ != nullptr; }
    //! False when Bfr has no surface for the face (holes).
    bool evaluate(std::size_t face, double u, double v, Vec2& out) {
        Bfr::Surface<double> surface;
        if (!factory_->InitFaceVaryingSurface(static_cast<int>(face), &surface, 0)) return false;
        std::vector<double> patch(2 * static_cast<std::size_t>(surface.GetNumPatchPoints()));
        surface.PreparePatchPoints(values_.data(), 2, patch.data(), 2);
        const double uv[2] = {u, v};
        double p[2];
        surface.Evaluate(uv, patch.data(), 2, p);
        out = {p[0], p[1]};
        return true;
    }

private:
    std::unique_ptr<Far::TopologyRefiner> refiner_;
    std::unique_ptr<Bfr::RefinerSurfaceFactory<>> factory_;
    std::vector<double> values_;
};

std::pair<double, double> random_uv(const PolygonMesh& mesh, std::size_t f, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const std::size_t n = mesh.face_size(f);
    if (n == 4) return {unit(rng), unit(rng)};
    const int columns = n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::sqrt(static_cast<double>(n - 1)));
    const int sub = static_cast<int>(rng() % n);
    return {sub % columns + 0.5 * unit(rng), sub / columns + 0.5 * unit(rng)};
}

using testing::with_seams;

using testing::load_opensubdiv_shape;

bool is_hole(const PolygonMesh& mesh, std::size_t f) {
    return std::find(mesh.tags.holes.begin(), mesh.tags.holes.end(), static_cast<Index>(f)) != mesh.tags.holes.end();
}

constexpr UvInterpolation kModes[] = {UvInterpolation::None,         UvInterpolation::CornersOnly,
                                      UvInterpolation::CornersPlus1, UvInterpolation::CornersPlus2,
                                      UvInterpolation::Boundaries,   UvInterpolation::All};

TEST(UvLimit, MatchesBfrFaceVaryingSurfacesInEveryMode) {
    std::vector<std::pair<std::string, PolygonMesh>> meshes = {
        {"seamed irregular_torus", with_seams(shapes::irregular_torus())},
        {"seamed mixed_polygons", with_seams(shapes::mixed_polygons())},
        {"seamed grid", with_seams([] {
             PolygonMesh g = shapes::grid(5, 4);
             for (Vec3& p : g.positions) p = Vec3{p.x - 0.5, p.y - 0.5, 0.1 * p.x * p.y};
             return g;
         }())},
    };
    for (const char* name : {"catmark_fvar_bound0", "catmark_fvar_bound1", "catmark_fvar_bound2", "catmark_fvar_bound3",
                             "catmark_fvar_bound4", "catmark_fvar_project0"})
        meshes.emplace_back(name, load_opensubdiv_shape(name));
    std::mt19937_64 rng(5);
    for (const auto& named : meshes) {
        const std::string& name = named.first;
        const PolygonMesh& mesh = named.second;
        ASSERT_TRUE(mesh.has_uvs()) << name;
        Vec2 lo = mesh.uvs[0], hi = mesh.uvs[0];
        for (const Vec2& uv : mesh.uvs)
            lo = {std::min(lo.x, uv.x), std::min(lo.y, uv.y)}, hi = {std::max(hi.x, uv.x), std::max(hi.y, uv.y)};
        const double size = std::hypot(hi.x - lo.x, hi.y - lo.y);
        for (const UvInterpolation mode : kModes) {
            SubdivisionOptions options;
            options.uv_interpolation = mode;
            auto ours = UvLimitEvaluator::create(mesh, options);
            ASSERT_TRUE(ours.ok()) << name << ": " << ours.error().message;
            BfrUvReference bfr(mesh, options);
            ASSERT_TRUE(bfr.valid()) << name;
            double worst = 0, worst_approximated = 0;
            int compared = 0;
            for (int i = 0; i < 200; ++i) {
                const std::size_t f = rng() % mesh.face_count();
                if (is_hole(mesh, f)) continue;
                const auto [u, v] = random_uv(mesh, f, rng);
                Vec2 ref;
                if (!bfr.evaluate(f, u, v, ref)) continue;
                auto sample = ours->evaluate(f, u, v);
                ASSERT_TRUE(sample.ok()) << name << " face " << f << ": " << sample.error().message;
                const double d = std::hypot(sample->uv.x - ref.x, sample->uv.y - ref.y);
                // inexact: a face with a value the value mesh approximates (or a point at an irregular value)
                double& slot = sample->exact ? worst : worst_approximated;
                slot = std::max(slot, d);
                if (sample->exact) {
                    EXPECT_LE(d, 1e-9 * size)
                        << name << " mode " << static_cast<int>(mode) << " face " << f << " (" << u << ", " << v << ")";
                }
                ++compared;
            }
            EXPECT_GT(compared, 100) << name;
            std::printf(
                "%-24s mode %d: %d points, worst |uv - Bfr| %.2e exact, %.2e inexact (UV extent %.2g, %zu "
                "approximated faces)\n",
                name.c_str(), static_cast<int>(mode), compared, worst, worst_approximated, size,
                ours->approximated_face_count());
        }
    }
}

//! Six quads around an interior vertex (valence 6), in two UV regions of three faces each (faces 0-2, 3-5), with
//! semi-sharp edges of the given sharpness between the faces of region 0 and UVs that are not a linear function of
//! position.
PolygonMesh two_region_fan(float sharp_a, float sharp_b) {
    PolygonMesh mesh;
    mesh.positions.push_back({0, 0, 0.2});
    for (int m = 0; m < 12; ++m) {
        const double angle = m * std::acos(-1.0) / 6, radius = m % 2 ? 1.3 : 1.0;
        mesh.positions.push_back({radius * std::cos(angle), radius * std::sin(angle), 0.1 * std::sin(3 * angle)});
    }
    const auto ring = [](int m) { return static_cast<Index>(1 + m % 12); };
    for (int k = 0; k < 6; ++k) mesh.add_face({0, ring(2 * k), ring(2 * k + 1), ring(2 * k + 2)});
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> jitter(-0.05, 0.05);
    std::vector<std::array<Index, 2>> value(mesh.vertex_count(), {kInvalidIndex, kInvalidIndex});
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (Index v : mesh.face(f)) {
            const int region = f < 3 ? 0 : 1;
            Index& id = value[v][static_cast<std::size_t>(region)];
            if (id == kInvalidIndex) {
                id = static_cast<Index>(mesh.uvs.size());
                const Vec3& p = mesh.positions[v];
                mesh.uvs.push_back({0.4 * p.x + 0.5 * region + jitter(rng), 0.4 * p.y + jitter(rng)});
            }
            mesh.uv_indices.push_back(id);
        }
    mesh.tags.creases.push_back({0, ring(2), sharp_a});                   // between faces 0 and 1
    if (sharp_b > 0) mesh.tags.creases.push_back({0, ring(4), sharp_b});  // between faces 1 and 2
    return mesh;
}

// corners-plus1/2 at a vertex with two UV regions, semi-sharp edges inside one of them: OpenSubdiv's dependent
// sharpness (uv_limit.h). Exact as a vertex sharpness when one edge decays last (uniform creasing, or Chaikin's on a
// single edge); otherwise the faces using the value are reported inexact and the difference is measured.
TEST(UvLimit, DependentSharpnessMatchesBfrOrIsReportedInexact) {
    struct Case {
        const char* name;
        UvInterpolation mode;
        CreaseMethod method;
        float a, b;
        bool exact;
    };
    std::mt19937_64 rng(3);
    for (const Case& c :
         {Case{"one edge", UvInterpolation::CornersPlus1, CreaseMethod::Uniform, 1.6f, 0, true},
          Case{"one edge", UvInterpolation::CornersPlus2, CreaseMethod::Uniform, 2.4f, 0, true},
          Case{"one edge, chaikin", UvInterpolation::CornersPlus1, CreaseMethod::Chaikin, 1.6f, 0, true},
          Case{"two edges", UvInterpolation::CornersPlus1, CreaseMethod::Uniform, 1.6f, 2.3f, true},
          Case{"two edges decaying last", UvInterpolation::CornersPlus1, CreaseMethod::Uniform, 1.6f, 1.3f, false},
          Case{"two edges, chaikin", UvInterpolation::CornersPlus1, CreaseMethod::Chaikin, 1.6f, 2.3f, false}}) {
        const PolygonMesh mesh = two_region_fan(c.a, c.b);
        SubdivisionOptions options;
        options.uv_interpolation = c.mode;
        options.crease_method = c.method;
        auto ours = UvLimitEvaluator::create(mesh, options);
        ASSERT_TRUE(ours.ok()) << c.name;
        EXPECT_EQ(ours->approximated_face_count() == 0, c.exact) << c.name;
        BfrUvReference bfr(mesh, options);
        double worst_exact = 0, worst_inexact = 0;
        for (int i = 0; i < 2000; ++i) {
            const std::size_t f = rng() % mesh.face_count();
            const auto [u, v] = random_uv(mesh, f, rng);
            Vec2 ref;
            ASSERT_TRUE(bfr.evaluate(f, u, v, ref));
            auto sample = ours->evaluate(f, u, v);
            ASSERT_TRUE(sample.ok());
            const double d = std::hypot(sample->uv.x - ref.x, sample->uv.y - ref.y);
            double& worst = sample->exact ? worst_exact : worst_inexact;
            worst = std::max(worst, d);
        }
        EXPECT_LE(worst_exact, 1e-12) << c.name;
        EXPECT_LE(worst_inexact, 2e-2) << c.name;  // the UV extent is about 1.5, the UVs' jitter 0.05
        std::printf(
            "dependent sharpness, %s (mode %d): %zu approximated faces, worst |uv - Bfr| %.2e there, %.2e "
            "elsewhere\n",
            c.name, static_cast<int>(c.mode), ours->approximated_face_count(), worst_inexact, worst_exact);
    }
}

TEST(UvLimit, ErrorsAreTheEvaluators) {
    PolygonMesh mesh = with_seams(shapes::cube());
    auto uvs = UvLimitEvaluator::create(mesh, {});
    ASSERT_TRUE(uvs.ok());
    EXPECT_EQ(uvs->evaluate(6, 0.5, 0.5).error().code, ErrorCode::IndexOutOfRange);
    EXPECT_EQ(uvs->evaluate(0, 1.5, 0.5).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(uvs->evaluate(0, NAN, 0.5).error().code, ErrorCode::NonFinite);
    EXPECT_EQ(UvLimitEvaluator::create(shapes::cube(), {}).error().code, ErrorCode::InvalidArgument);  // no UVs
    SubdivisionOptions all;
    all.uv_interpolation = UvInterpolation::All;
    auto linear = UvLimitEvaluator::create(mesh, all);
    ASSERT_TRUE(linear.ok());
    EXPECT_EQ(linear->evaluate(6, 0.5, 0.5).error().code, ErrorCode::IndexOutOfRange);
    EXPECT_EQ(linear->evaluate(0, 0.5, 1.01).error().code, ErrorCode::InvalidArgument);
}

TEST(UvLimit, DomainIsBfrsTiling) {
    EXPECT_TRUE(limit_domain_contains(4, 1, 1));
    EXPECT_FALSE(limit_domain_contains(4, 1.01, 0));
    // a triangle: tiles (0, 0), (1, 0), (0, 1), each [x, x + 1/2] x [y, y + 1/2]
    EXPECT_TRUE(limit_domain_contains(3, 1.5, 0.5));
    EXPECT_TRUE(limit_domain_contains(3, 0.25, 1.25));
    EXPECT_FALSE(limit_domain_contains(3, 1.25, 1.25));  // a fourth tile does not exist
    EXPECT_FALSE(limit_domain_contains(3, 0.75, 0.25));  // between tiles
    // a pentagon: three tiles per row
    EXPECT_TRUE(limit_domain_contains(5, 2.5, 0.5));
    EXPECT_TRUE(limit_domain_contains(5, 1.5, 1.5));
    EXPECT_FALSE(limit_domain_contains(5, 2.25, 1.25));
}

}  // namespace
}  // namespace surfaced
