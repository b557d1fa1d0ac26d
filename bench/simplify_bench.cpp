// simplify_qem against meshoptimizer's meshopt_simplify (Debian libmeshoptimizer-dev; bench only, never linked into
// the service), on the same triangles, at 10% and 1% of the faces. Prints a Markdown table: time, faces reached,
// symmetric Hausdorff and two-sided RMS distance to the input (mesh_distance, same sampling for both), and the
// invariants we promise (non-manifold edges, duplicate faces).
//
// Usage: bench_simplify [--quick]   (--quick skips the 1M-triangle meshes)
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <meshoptimizer.h>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/simplify/mesh_distance.h"
#include "geometry/simplify/qem.h"
#include "geometry/subdivision/subdivide.h"

namespace {

using namespace surfaced;
using Clock = std::chrono::steady_clock;

struct Row {
    std::size_t faces = 0;
    double seconds = 0, hausdorff = 0, rms = 0;
    std::size_t non_manifold = 0, duplicates = 0;
};

PolygonMesh icosphere(int levels) {
    SubdivisionOptions options;
    options.scheme = SubdivisionScheme::Loop;
    options.levels = levels;
    PolygonMesh mesh = subdivide(shapes::icosahedron(), options).value();
    for (Vec3& p : mesh.positions) p *= 1.0 / norm(p);
    return mesh;
}

//! Edges used by more than two faces, and faces on the same vertex set as another.
void invariants(const PolygonMesh& mesh, Row& row) {
    std::vector<std::uint64_t> edges, faces;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        std::array<Index, 3> key{t[0], t[1], t[2]};
        std::sort(key.begin(), key.end());
        faces.push_back((std::uint64_t{key[0]} << 42) ^ (std::uint64_t{key[1]} << 21) ^ key[2]);
        for (int j = 0; j < 3; ++j) {
            const Index a = t[j], b = t[(j + 1) % 3];
            edges.push_back((std::uint64_t{std::min(a, b)} << 32) | std::max(a, b));
        }
    }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        row.non_manifold += j - i > 2;
        i = j;
    }
    std::sort(faces.begin(), faces.end());
    for (std::size_t i = 1; i < faces.size(); ++i) row.duplicates += faces[i] == faces[i - 1];
}

void measure(const PolygonMesh& input, const PolygonMesh& output, Row& row) {
    const MeshDistance d = mesh_distance(input, output);
    row.hausdorff = d.hausdorff;
    row.rms = d.rms;
    row.faces = output.face_count();
    invariants(output, row);
}

Row ours(const PolygonMesh& input, std::size_t target) {
    SimplifyOptions options;
    options.target_faces = target;
    const auto start = Clock::now();
    auto result = simplify_qem(input, options);
    Row row;
    row.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (!result) {
        std::fprintf(stderr, "simplify_qem failed: %s\n", result.error().message.c_str());
        return row;
    }
    measure(input, result->mesh, row);
    return row;
}

Row meshopt(const PolygonMesh& input, std::size_t target) {
    std::vector<float> positions;
    positions.reserve(3 * input.vertex_count());
    for (const Vec3& p : input.positions) {
        positions.push_back(static_cast<float>(p.x));
        positions.push_back(static_cast<float>(p.y));
        positions.push_back(static_cast<float>(p.z));
    }
    std::vector<unsigned int> indices(input.face_indices.begin(), input.face_indices.end());
    std::vector<unsigned int> out(indices.size());
    const auto start = Clock::now();
    float error = 0;
    // target_error 1 (relative): no error limit, stop at the count, as simplify_qem does with target_faces alone
    const std::size_t count = meshopt_simplify(out.data(), indices.data(), indices.size(), positions.data(),
                                               input.vertex_count(), 3 * sizeof(float), 3 * target, 1.0f, 0, &error);
    Row row;
    row.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    // meshopt keeps the original vertex buffer; drop unused vertices so that every vertex sampled is on the surface
    PolygonMesh mesh;
    std::vector<Index> remap(input.vertex_count(), kInvalidIndex);
    for (std::size_t i = 0; i < count; ++i) {
        const Index v = out[i];
        if (remap[v] == kInvalidIndex) {
            remap[v] = static_cast<Index>(mesh.positions.size());
            mesh.positions.push_back(input.positions[v]);
        }
        mesh.face_indices.push_back(remap[v]);
        if (i % 3 == 2) mesh.face_offsets.push_back(static_cast<Index>(mesh.face_indices.size()));
    }
    measure(input, mesh, row);
    return row;
}

void run(const std::string& name, const PolygonMesh& mesh) {
    const double diagonal = mesh.bounds().diagonal();
    for (double ratio : {0.1, 0.01}) {
        const auto target = static_cast<std::size_t>(ratio * static_cast<double>(mesh.face_count()));
        const Row a = ours(mesh, target);
        const Row b = meshopt(mesh, target);
        auto ratio_text = [](double x, double y) { return y > 0 ? x / y : 0.0; };
        std::printf("| %s | %zu | %g%% | %.3f / %.3f (%.2fx) | %zu / %zu | %.2e / %.2e (%.2fx) | %.2e / %.2e (%.2fx) | "
                    "%zu / %zu | %zu / %zu |\n",
                    name.c_str(), mesh.face_count(), ratio * 100, a.seconds, b.seconds, ratio_text(a.seconds, b.seconds),
                    a.faces, b.faces, a.hausdorff / diagonal, b.hausdorff / diagonal,
                    ratio_text(a.hausdorff, b.hausdorff), a.rms / diagonal, b.rms / diagonal, ratio_text(a.rms, b.rms),
                    a.non_manifold, b.non_manifold, a.duplicates, b.duplicates);
        std::fflush(stdout);
    }
}

}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    std::printf("ours / meshoptimizer %d.%d; errors relative to the bounding-box diagonal; time in seconds\n\n",
                MESHOPTIMIZER_VERSION / 1000, MESHOPTIMIZER_VERSION % 1000 / 10);
    std::printf("| mesh | triangles | target | time | faces | Hausdorff | RMS | non-manifold edges | duplicate faces |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    const char* bunny_path = "/usr/share/glmark2/models/bunny.obj";
    if (std::filesystem::exists(bunny_path)) {
        std::ifstream in(bunny_path, std::ios::binary);
        std::stringstream text;
        text << in.rdbuf();
        auto bunny = read_obj(text.str());
        if (bunny) run("bunny (glmark2-data)", bunny.value());
    } else {
        std::fprintf(stderr, "%s missing (Debian glmark2-data): bunny skipped\n", bunny_path);
    }
    run("icosphere 6", icosphere(6));
    if (!quick) {
        run("icosphere 8", icosphere(8));
        run("torus 1024x512", triangulate(shapes::torus(1024, 512)));
    }
    return 0;
}
