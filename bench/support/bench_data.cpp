#include "bench/support/bench_data.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <utility>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/subdivide.h"

namespace surfaced::bench {

PolygonMesh read_bunny() {
    std::ifstream in(kBunnyPath, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    auto mesh = read_obj(text.str());
    if (!mesh) {
        std::fprintf(stderr, "%s missing or unreadable\n", kBunnyPath);
        return {};
    }
    return std::move(mesh.value());
}

PolygonMesh read_opensubdiv_shape(const std::string& name) {
    const std::string path = SURFACED_SOURCE_DIR "/tests/data/opensubdiv-shapes/" + name + ".obj";
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    ReadOptions options;
    options.allow_repeated_vertices = true;  // some shapes have faces that use a vertex twice
    auto mesh = read_obj(text.str(), options);
    if (!mesh) {
        std::fprintf(stderr, "%s missing or unreadable\n", path.c_str());
        return {};
    }
    return std::move(mesh.value());
}

PolygonMesh icosphere(int levels) {
    SubdivisionOptions options;
    options.scheme = SubdivisionScheme::Loop;
    options.levels = levels;
    PolygonMesh mesh = subdivide(shapes::icosahedron(), options).value();
    for (Vec3& p : mesh.positions) p *= 1.0 / norm(p);
    return mesh;
}

}  // namespace surfaced::bench
