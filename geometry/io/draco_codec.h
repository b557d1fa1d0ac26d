// Internal to geo_gltf: a Draco triangle-mesh codec over plain arrays, so that Draco's headers stay in one TU
// (draco_codec.cpp). The layout matches glTF accessors: float components per point, three indices per triangle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "geometry/core/result.h"

namespace surfaced::draco_codec {

//! Per-point attributes plus a triangle list. normals / texcoords are empty when absent.
struct MeshData {
    std::vector<float> positions;        //!< 3 per point
    std::vector<float> normals;          //!< 3 per point, or empty
    std::vector<float> texcoords;        //!< 2 per point, or empty
    std::vector<float> colors;           //!< color_components channels in 0..1 per point, or empty
    int color_components = 3;            //!< 3 (RGB) or 4 (RGBA)
    std::vector<std::uint32_t> indices;  //!< 3 per triangle, each < point count

    std::size_t point_count() const { return positions.size() / 3; }
    std::size_t triangle_count() const { return indices.size() / 3; }
};

struct EncodeOptions {
    int quantize_position = 14;  //!< 1..30 for Draco; write_glb allows 1..24 (cost doubles per bit)
    int quantize_normal = 10;    //!< 2..30 for Draco; write_glb allows 2..22 (cost grows 4x per bit)
    int quantize_texcoord = 12;  //!< 1..30 for Draco; write_glb allows 1..24
    int encode_speed = 5;        //!< 0..10
    int decode_speed = 5;        //!< 0..10
};

//! Draco attribute unique ids, as KHR_draco_mesh_compression's `attributes` maps them; -1 = absent.
struct AttributeIds {
    int position = -1;
    int normal = -1;
    int texcoord = -1;
    int color = -1;
};

struct Encoded {
    std::string bytes;  //!< the Draco bitstream (the glTF bufferView payload)
    AttributeIds ids;
};

//! Draco quantizes positions over their bounding box, whose extent it computes in float32: an extent beyond the
//! float32 range (coordinates of both signs near 3.4e38) would overflow to infinity, on which the encoder crashes.
//! InvalidArgument naming the axis and the extent when `positions` (x, y, z floats) have one.
Status check_quantizable_positions(const std::vector<float>& positions);

//! Encodes `mesh` (preconditions: positions non-empty, sizes consistent, indices in range; options in range).
//! Colours are stored as normalised unsigned bytes (clamped to 0..1), as glTF COLOR_0 allows.
//! Errors: InvalidArgument for positions Draco cannot quantize (check_quantizable_positions), Internal when Draco
//! rejects the input.
Result<Encoded> encode(const MeshData& mesh, const EncodeOptions& options);

struct DecodeLimits {
    std::size_t max_points = 0;
    std::size_t max_triangles = 0;
};

//! The counts a Draco mesh stream announces in its connectivity header: Draco sizes its buffers by them before it
//! reads the data they describe, so a few bytes could ask for gigabytes; decode refuses them over its limits first.
//! The header is "DRACO", major, minor, encoder type (1: triangular mesh), method (0: sequential, then the face and
//! point counts; 1: edgebreaker, then its traversal type and the vertex and face counts), uint16 flags. `points`
//! is the encoded vertex count (edgebreaker splits vertices on attribute seams, at most 3 per face). ParseError for a
//! stream that is not a Draco mesh, ends in the header, or has metadata (flag 0x8000, which would hide the counts).
struct AnnouncedCounts {
    std::uint32_t faces = 0, points = 0;
};
Result<AnnouncedCounts> announced_mesh_counts(std::span<const std::uint8_t> bytes);

//! Decodes a Draco mesh and extracts the attributes named by `ids` (position required; normal/texcoord/color
//! optional, -1 = skip) as floats (normalised integer colours as 0..1). Every index and attribute mapping is checked.
//! Errors: ParseError (not a valid Draco mesh, missing attribute, wrong component count), BudgetExceeded (beyond
//! `limits`, from the announced counts before Draco allocates, and from the decoded ones).
Result<MeshData> decode(std::span<const std::uint8_t> bytes, const AttributeIds& ids, const DecodeLimits& limits);

}  // namespace surfaced::draco_codec
