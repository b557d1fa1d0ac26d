// surfaced::Cancel in the long-running algorithms: a fired Cancel (deadline passed, or the abort flag set) stops
// subdivision, simplification and patch tessellation with ErrorCode::Cancelled; a default one changes nothing.
#include <gtest/gtest.h>

#include <atomic>

#include "geometry/core/cancel.h"
#include "geometry/io/bez.h"
#include "geometry/mesh/shapes.h"
#include "geometry/simplify/qem.h"
#include "geometry/subdivision/subdivide.h"
#include "geometry/surfaces/bezier_patch.h"

namespace surfaced {
namespace {

Cancel past_deadline() {
    Cancel cancel;
    cancel.deadline = Cancel::Clock::now() - std::chrono::milliseconds(1);
    return cancel;
}

TEST(Cancel, DefaultNeverFiresAndFlagOrDeadlineDo) {
    EXPECT_FALSE(Cancel{}.requested());
    EXPECT_TRUE(past_deadline().requested());
    std::atomic<bool> flag{false};
    Cancel with_flag;
    with_flag.flag = &flag;
    EXPECT_FALSE(with_flag.requested());
    flag = true;
    EXPECT_TRUE(with_flag.requested());
}

TEST(Cancel, StopsSubdivision) {
    SubdivisionOptions options;
    options.levels = 3;
    auto full = subdivide(shapes::torus(16, 8), options);
    ASSERT_TRUE(full);
    EXPECT_EQ(full->face_count(), 16u * 8u * 64u);
    options.cancel = past_deadline();
    auto cancelled = subdivide(shapes::torus(16, 8), options);
    ASSERT_FALSE(cancelled);
    EXPECT_EQ(cancelled.error().code, ErrorCode::Cancelled);
}

TEST(Cancel, StopsSimplification) {
    SubdivisionOptions refine;
    refine.scheme = SubdivisionScheme::Loop;
    refine.levels = 5;
    auto sphere = subdivide(shapes::icosahedron(), refine);  // 20480 triangles: ~9000 collapses, past the first poll
    ASSERT_TRUE(sphere);
    SimplifyOptions options;
    options.ratio = 0.1;
    auto full = simplify_qem(*sphere, options);
    ASSERT_TRUE(full);
    EXPECT_LE(full->faces, 2048u);
    for (const bool with_max_error : {false, true}) {
        SimplifyOptions cancelled_options = options;
        if (with_max_error) cancelled_options.max_error = 0.05;
        cancelled_options.cancel = past_deadline();
        auto cancelled = simplify_qem(*sphere, cancelled_options);
        ASSERT_FALSE(cancelled) << with_max_error;
        EXPECT_EQ(cancelled.error().code, ErrorCode::Cancelled);
    }
}

TEST(Cancel, StopsPatchTessellation) {
    auto teapot = read_bez(patch_sample_text("teapot"));
    ASSERT_TRUE(teapot);
    TessellationOptions options;
    options.segments = 4;
    auto full = tessellate_patches(teapot->patches, options);
    ASSERT_TRUE(full);
    EXPECT_GT(full->mesh.face_count(), 0u);
    options.cancel = past_deadline();
    auto cancelled = tessellate_patches(teapot->patches, options);
    ASSERT_FALSE(cancelled);
    EXPECT_EQ(cancelled.error().code, ErrorCode::Cancelled);
}

}  // namespace
}  // namespace surfaced
