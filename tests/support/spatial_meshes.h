// Meshes and brute-force references shared by the spatial query tests (hierarchy, closest point, rays, winding
// numbers). Header-only, as simplify_meshes.h.
#pragma once

#include <cmath>
#include <filesystem>
#include <optional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/polygon_mesh.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/simplify_meshes.h"

namespace surfaced::testing {

// The Stanford bunny (tests/data/bunny): 34835 vertices, 69666 triangles.
inline constexpr const char* kSpatialBunnyPath = SURFACED_TEST_DATA_DIR "/bunny/bunny.obj";

//! Read once per test binary (several tests use it).
inline const PolygonMesh& spatial_bunny() {
    static const PolygonMesh bunny = [] {
        if (!std::filesystem::exists(kSpatialBunnyPath)) return PolygonMesh{};
        auto mesh = read_obj(read_file(kSpatialBunnyPath));
        return mesh.ok() ? std::move(mesh.value()) : PolygonMesh{};
    }();
    if (bunny.face_count() == 0) ADD_FAILURE() << kSpatialBunnyPath << " is missing or unreadable";
    return bunny;
}

//! Uniform point in the box grown by `margin` times its diagonal on every side.
inline Vec3 random_point(std::mt19937_64& rng, const Box3& box, double margin) {
    const double pad = margin * box.diagonal();
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return {box.min.x - pad + u(rng) * (box.max.x - box.min.x + 2 * pad),
            box.min.y - pad + u(rng) * (box.max.y - box.min.y + 2 * pad),
            box.min.z - pad + u(rng) * (box.max.z - box.min.z + 2 * pad)};
}

inline Vec3 random_unit(std::mt19937_64& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    for (;;) {
        const Vec3 v{n(rng), n(rng), n(rng)};
        const double len = norm(v);
        if (len > 1e-3) return v * (1.0 / len);
    }
}

//! Two meshes in one (no welding): the second's vertices are renumbered after the first's.
inline PolygonMesh concatenate(const PolygonMesh& a, const PolygonMesh& b) {
    PolygonMesh out = a;
    out.tags = {};
    const auto base = static_cast<Index>(a.positions.size());
    out.positions.insert(out.positions.end(), b.positions.begin(), b.positions.end());
    for (std::size_t f = 0; f < b.face_count(); ++f) {
        std::vector<Index> face;
        for (Index v : b.face(f)) face.push_back(v + base);
        out.add_face(face);
    }
    return out;
}

//! The mesh translated by t.
inline PolygonMesh translated(PolygonMesh mesh, const Vec3& t) {
    for (Vec3& p : mesh.positions) p += t;
    return mesh;
}

//! The mesh without the faces whose centroid `drop` says to remove (unused vertices stay).
template <class Drop>
PolygonMesh without_faces(const PolygonMesh& mesh, Drop drop) {
    PolygonMesh out;
    out.positions = mesh.positions;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        Vec3 c;
        for (Index v : mesh.face(f)) c += mesh.positions[v];
        c *= 1.0 / static_cast<double>(mesh.face_size(f));
        if (!drop(c)) out.add_face(mesh.face(f));
    }
    return out;
}

}  // namespace surfaced::testing
