// The Draco mesh codec's guard against streams that announce more than the limits: the counts read from the
// connectivity header agree with what our encoder wrote (edgebreaker and sequential), and a stream announcing a huge
// mesh in a few bytes is refused before Draco sizes anything by it.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/io/draco_codec.h"

namespace surfaced {
namespace {

//! A (n + 1) x (n + 1) grid of points, two triangles per cell, with normals.
draco_codec::MeshData grid(int n) {
    draco_codec::MeshData mesh;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            mesh.positions.insert(mesh.positions.end(), {float(i), float(j), float((i * j) % 5) * 0.1f});
            mesh.normals.insert(mesh.normals.end(), {0.0f, 0.0f, 1.0f});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto v = std::uint32_t(j * (n + 1) + i), w = v + std::uint32_t(n + 1);
            mesh.indices.insert(mesh.indices.end(), {v, v + 1, w + 1, v, w + 1, w});
        }
    return mesh;
}

std::span<const std::uint8_t> bytes_of(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

void put_varint(std::vector<std::uint8_t>& out, std::uint32_t value) {
    do {
        const std::uint8_t low = value & 0x7f;
        value >>= 7;
        out.push_back(value ? std::uint8_t(low | 0x80) : low);
    } while (value);
}

TEST(DracoCodec, AnnouncedCountsAgreeWithTheEncodedMesh) {
    const draco_codec::MeshData mesh = grid(12);
    for (int speed : {5, 10}) {  // edgebreaker; speed 10 is Draco's sequential encoding
        SCOPED_TRACE(speed);
        draco_codec::EncodeOptions options;
        options.encode_speed = options.decode_speed = speed;
        auto encoded = draco_codec::encode(mesh, options);
        ASSERT_TRUE(encoded.ok()) << encoded.error().message;
        const auto stream = bytes_of(encoded->bytes);
        EXPECT_EQ(stream[8], speed == 10 ? 0 : 1);  // the method byte
        auto counts = draco_codec::announced_mesh_counts(stream);
        ASSERT_TRUE(counts.ok()) << counts.error().message;
        EXPECT_EQ(counts->faces, mesh.triangle_count());
        EXPECT_EQ(counts->points, mesh.point_count());
        // the limits hold on the announced counts
        auto decoded = draco_codec::decode(stream, encoded->ids, {mesh.point_count(), mesh.triangle_count()});
        ASSERT_TRUE(decoded.ok()) << decoded.error().message;
        EXPECT_EQ(decoded->triangle_count(), mesh.triangle_count());
        auto over = draco_codec::decode(stream, encoded->ids, {mesh.point_count(), mesh.triangle_count() - 1});
        ASSERT_FALSE(over.ok());
        EXPECT_EQ(over.error().code, ErrorCode::BudgetExceeded);
        EXPECT_NE(over.error().message.find("announces 288 triangles"), std::string::npos) << over.error().message;
    }
}

TEST(DracoCodec, HugeAnnouncedMeshIsRefusedBeforeDecoding) {
    auto encoded = draco_codec::encode(grid(4), {});
    ASSERT_TRUE(encoded.ok());
    const auto valid = bytes_of(encoded->bytes);
    // the same header and traversal type, then 2^31 - 1 faces on 100 vertices, and the rest of the stream
    std::vector<std::uint8_t> stream(valid.begin(), valid.begin() + 12);
    put_varint(stream, 100);
    put_varint(stream, 0x7fffffff);
    stream.insert(stream.end(), valid.begin() + 14, valid.end());
    auto decoded = draco_codec::decode(stream, encoded->ids, {1'000'000, 1'000'000});
    ASSERT_FALSE(decoded.ok());
    EXPECT_EQ(decoded.error().code, ErrorCode::BudgetExceeded);
    EXPECT_NE(decoded.error().message.find("announces 2147483647 triangles"), std::string::npos)
        << decoded.error().message;
    // a stream cut inside the connectivity header, metadata, a point cloud and another method are parse errors
    for (std::size_t cut : {std::size_t(5), std::size_t(11), std::size_t(13)})
        EXPECT_EQ(draco_codec::decode(std::span(stream).first(cut), encoded->ids, {10, 10}).error().code,
                  ErrorCode::ParseError)
            << cut;
    for (const auto& [at, value] : {std::pair{10, 0x80}, std::pair{7, 0}, std::pair{8, 7}}) {
        std::vector<std::uint8_t> changed(valid.begin(), valid.end());
        changed[std::size_t(at)] = std::uint8_t(value);
        EXPECT_EQ(draco_codec::decode(changed, encoded->ids, {1'000'000, 1'000'000}).error().code,
                  ErrorCode::ParseError)
            << at;
    }
}

}  // namespace
}  // namespace surfaced
