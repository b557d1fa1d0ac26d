// POST /limit/evaluate against the geometry it calls: points per second through the operation (JSON and packed
// float64 bodies, decoded, evaluated and encoded; the request body built beforehand) and through
// LimitSurfaceEvaluator alone, on the same random points in random face order, one thread. A second table measures
// where preparing a face (face_surface) starts to pay: k points on each face, evaluated one by one or through the
// face's prepared surface (its set-up included), which sets the operation's kFaceSurfacePoints.
//
// Usage: bench_limit_api [--quick]
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "api/routes.h"
#include "geometry/io/base64.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "bench/support/timing.h"

namespace {

using namespace surfaced;

struct Point {
    std::size_t face;
    double u, v;
};

//! Random points on the quads of `mesh`, in random face order.
std::vector<Point> random_points(const PolygonMesh& mesh, std::size_t count, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<std::size_t> quads;
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        if (mesh.face_size(f) == 4) quads.push_back(f);
    std::vector<Point> out;
    for (std::size_t i = 0; i < count; ++i) out.push_back({quads[rng() % quads.size()], unit(rng), unit(rng)});
    return out;
}

std::string number(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", x);
    return text;
}

//! {"mesh": {...}, (the request's JSON mesh) without the closing brace
std::string mesh_member(const PolygonMesh& mesh) {
    std::string out = R"({"mesh":{"positions":[)";
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const Vec3& p = mesh.positions[i];
        out += (i ? ",[" : "[") + number(p.x) + "," + number(p.y) + "," + number(p.z) + "]";
    }
    out += R"(],"faces":[)";
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        out += f ? ",[" : "[";
        const auto face = mesh.face(f);
        for (std::size_t k = 0; k < face.size(); ++k) out += (k ? "," : "") + std::to_string(face[k]);
        out += "]";
    }
    return out + "]}";
}

double operation_seconds(const std::string& body) {
    api::ApiRequest request;
    request.method = "POST";
    request.path = "/limit/evaluate";
    request.content_type = "application/json";
    request.body = body;
    const bench::Stopwatch watch;
    const api::ApiResponse response = api::dispatch(request, api::ApiContext{});
    const double seconds = watch.seconds();
    if (response.status != 200) std::printf("status %d: %.200s\n", response.status, response.body.c_str());
    return seconds;
}

void run(const char* name, const PolygonMesh& mesh, std::size_t count) {
    const std::vector<Point> points = random_points(mesh, count, 7);
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    double checksum = 0;
    const bench::Stopwatch watch;
    for (const Point& p : points) checksum += evaluator->evaluate(p.face, p.u, p.v)->position.x;
    const double geometry = watch.seconds();

    std::string list;
    std::string packed;
    for (const Point& p : points) {
        list += (list.empty() ? R"({"face":)" : R"(,{"face":)") + std::to_string(p.face) + R"(,"uv":[)" + number(p.u) +
                "," + number(p.v) + "]}";
        for (const double x : {static_cast<double>(p.face), p.u, p.v}) {
            const auto bits = std::bit_cast<std::uint64_t>(x);
            for (int b = 0; b < 8; ++b) packed += static_cast<char>((bits >> (8 * b)) & 0xff);
        }
    }
    const std::string mesh_text = mesh_member(mesh);
    const double json = operation_seconds(mesh_text + R"(,"points":[)" + list + "]}");
    const double binary = operation_seconds(mesh_text + R"(,"points":{"float64":")" + encode_base64(packed) +
                                            R"("},"encoding":"float64"})");
    std::printf("%-22s %6zu %8zu %12.3g %12.3g %12.3g   %.2f %.2f\n", name, mesh.face_count(), count, count / geometry,
                count / json, count / binary, geometry / json, geometry / binary);
    if (checksum == 12345.678) std::printf("\n");  // keeps the loop
}

//! k points on every face: one evaluate() each, or face_surface() once and its evaluate() per point.
void prepared(const char* name, const PolygonMesh& mesh, std::size_t k) {
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<Point> points;
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        if (mesh.face_size(f) == 4)
            for (std::size_t i = 0; i < k; ++i) points.push_back({f, unit(rng), unit(rng)});
    const int repeats = static_cast<int>(std::max<std::size_t>(1, 20000 / points.size()));
    double checksum = 0;
    bench::Stopwatch watch;
    for (int r = 0; r < repeats; ++r)
        for (const Point& p : points) checksum += evaluator->evaluate(p.face, p.u, p.v)->position.x;
    const double single = watch.seconds();
    watch.restart();
    for (int r = 0; r < repeats; ++r)
        for (std::size_t i = 0; i < points.size(); i += k) {
            auto surface = evaluator->face_surface(points[i].face);
            for (std::size_t j = i; j < i + k; ++j) checksum += surface->evaluate(points[j].u, points[j].v)->position.x;
        }
    const double grouped = watch.seconds();
    std::printf("%-22s %4zu %12.3g %12.3g   %.2f\n", name, k, repeats * points.size() / single,
                repeats * points.size() / grouped, single / grouped);
    if (checksum == 12345.678) std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const std::size_t count = quick ? 20000 : 200000;
    std::printf(
        "POST /limit/evaluate vs LimitSurfaceEvaluator::evaluate, random points in random face order, "
        "position + du + dv + normal, one thread; points/s\n");
    std::printf("%-22s %6s %8s %12s %12s %12s   %s\n", "mesh", "faces", "points", "geometry", "op json", "op float64",
                "op/geometry (json, float64)");
    run("torus 32x24 (regular)", shapes::torus(32, 24), count);
    run("irregular_torus", shapes::irregular_torus(), count);
    run("cube (valence 3)", shapes::cube(), count);
    std::printf(
        "\nk points per face: evaluate() each vs face_surface() once + evaluate() each (set-up included); "
        "points/s\n");
    std::printf("%-22s %4s %12s %12s   %s\n", "mesh", "k", "evaluate", "face_surface", "speedup");
    for (const std::size_t k : {1, 2, 4, 8, 16, 64, 256}) prepared("irregular_torus", shapes::irregular_torus(), k);
    for (const std::size_t k : {1, 4, 8, 16, 64}) prepared("cube (valence 3)", shapes::cube(), k);
    return 0;
}
