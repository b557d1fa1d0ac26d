// The OpenSubdiv regression shapes of tests/data/opensubdiv-shapes, read as the limit-surface tests read them: faces
// may use a vertex twice, as OpenSubdiv allows.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "geometry/io/mesh_io.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::testing {

//! The shape `name` (file name without .obj); a failed test and an empty mesh when it cannot be read.
inline PolygonMesh load_opensubdiv_shape(const std::string& name) {
    ReadOptions read_options;
    read_options.allow_repeated_vertices = true;
    const std::filesystem::path path =
        std::filesystem::path(SURFACED_TEST_DATA_DIR) / "opensubdiv-shapes" / (name + ".obj");
    auto mesh = read_obj(read_file(path.string()), read_options);
    EXPECT_TRUE(mesh.ok()) << name;
    return mesh.ok() ? *mesh : PolygonMesh{};
}

}  // namespace surfaced::testing
