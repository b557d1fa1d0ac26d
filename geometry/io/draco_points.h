// Internal to geo_gltf: a Draco point-cloud codec over plain arrays (no triangles), so that Draco's headers stay in
// one TU (draco_points.cpp). Colours are written as 8-bit normalised RGB or RGBA, as glTF COLOR_0 stores them; they
// are read from any Draco colour type, as 0..1 channels for a normalised one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/io/draco_codec.h"

namespace surfaced::draco_points {

struct PointData {
    std::vector<float> positions;  //!< 3 per point
    std::vector<float> normals;    //!< 3 per point, or empty
    std::vector<float> colors;     //!< color_components channels per point (0..1 when normalised), or empty
    int color_components = 3;      //!< 3 (RGB) or 4 (RGBA)

    std::size_t point_count() const { return positions.size() / 3; }
};

struct AttributeIds {
    int position = -1, normal = -1, color = -1;  //!< Draco unique ids; -1 = absent
};

struct Encoded {
    std::string bytes;
    AttributeIds ids;
};

//! Encodes a point cloud (Draco may reorder the points; all attributes stay together). Position, normal and colour
//! quantization as in draco_codec::EncodeOptions (texcoord bits unused); colours (0..1, clamped) as unsigned bytes.
//! Errors: Internal, BudgetExceeded (memory).
Result<Encoded> encode(const PointData& points, const draco_codec::EncodeOptions& options);

//! Decodes a Draco point cloud (or the points of a Draco mesh), extracting the attributes named by `ids` (position
//! required). Colours come as Draco converts them to float: normalised integers to 0..1, other types as stored.
//! Errors: ParseError (not Draco, missing attribute, wrong component count), BudgetExceeded (more than max_points).
Result<PointData> decode(std::span<const std::uint8_t> bytes, const AttributeIds& ids, std::size_t max_points);

}  // namespace surfaced::draco_points
