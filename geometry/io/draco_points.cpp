// The only TU that includes Draco's point-cloud headers. As in draco_codec.cpp, anything Draco throws (bad_alloc)
// is turned into a GeoError here.
#include "geometry/io/draco_points.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <string_view>

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/point_cloud/point_cloud.h>

namespace surfaced::draco_points {
namespace {

template <class T>
int add_attribute(draco::PointCloud& cloud, draco::GeometryAttribute::Type type, draco::DataType data_type,
                  bool normalized, int components, const std::vector<T>& values) {
    draco::GeometryAttribute layout;
    layout.Init(type, nullptr, static_cast<std::uint8_t>(components), data_type, normalized,
                static_cast<std::int64_t>(sizeof(T)) * components, 0);
    const std::size_t count = values.size() / static_cast<std::size_t>(components);
    const int att_id = cloud.AddAttribute(layout, true, static_cast<std::uint32_t>(count));
    draco::PointAttribute* attribute = cloud.attribute(att_id);
    for (std::size_t i = 0; i < count; ++i)
        attribute->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(i)),
                                     values.data() + i * static_cast<std::size_t>(components));
    return att_id;
}

Result<Encoded> encode_unchecked(const PointData& data, const draco_codec::EncodeOptions& options) {
    if (Status quantizable = draco_codec::check_quantizable_positions(data.positions); !quantizable)
        return std::move(quantizable.error());
    draco::PointCloud cloud;
    cloud.set_num_points(static_cast<std::uint32_t>(data.point_count()));
    const int position =
        add_attribute(cloud, draco::GeometryAttribute::POSITION, draco::DT_FLOAT32, false, 3, data.positions);
    const int normal = data.normals.empty() ? -1
                                            : add_attribute(cloud, draco::GeometryAttribute::NORMAL, draco::DT_FLOAT32,
                                                            false, 3, data.normals);
    std::vector<std::uint8_t> bytes;
    bytes.reserve(data.colors.size());
    for (float c : data.colors)
        bytes.push_back(static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f)));
    const int color = data.colors.empty() ? -1
                                          : add_attribute(cloud, draco::GeometryAttribute::COLOR, draco::DT_UINT8, true,
                                                          data.color_components, bytes);
    Encoded out;
    out.ids.position = static_cast<int>(cloud.attribute(position)->unique_id());
    if (normal >= 0) out.ids.normal = static_cast<int>(cloud.attribute(normal)->unique_id());
    if (color >= 0) out.ids.color = static_cast<int>(cloud.attribute(color)->unique_id());

    draco::Encoder encoder;
    encoder.SetSpeedOptions(options.encode_speed, options.decode_speed);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, options.quantize_position);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, options.quantize_normal);
    draco::EncoderBuffer buffer;
    const draco::Status status = encoder.EncodePointCloudToBuffer(cloud, &buffer);
    if (!status.ok())
        return make_error(ErrorCode::Internal, std::string("Draco encoder failed: ") + status.error_msg());
    out.bytes.assign(buffer.data(), buffer.size());
    return out;
}

template <class T>
Result<std::vector<T>> extract(const draco::PointCloud& cloud, int unique_id, int components, const char* name) {
    const draco::PointAttribute* attribute = cloud.GetAttributeByUniqueId(static_cast<std::uint32_t>(unique_id));
    if (attribute == nullptr)
        return make_error(ErrorCode::ParseError, std::string("Draco data has no attribute with id ") +
                                                     std::to_string(unique_id) + " (" + name + ")");
    if (attribute->num_components() != components)
        return make_error(ErrorCode::ParseError, std::string("Draco attribute ") + name + " has " +
                                                     std::to_string(attribute->num_components()) +
                                                     " components, expected " + std::to_string(components));
    const std::size_t points = cloud.num_points();
    if (!attribute->is_mapping_identity() && attribute->indices_map_size() < points)
        return make_error(ErrorCode::ParseError, std::string("Draco attribute ") + name + " does not map every point");
    std::vector<T> values(points * static_cast<std::size_t>(components));
    for (std::size_t p = 0; p < points; ++p) {
        const draco::AttributeValueIndex avi =
            attribute->mapped_index(draco::PointIndex(static_cast<std::uint32_t>(p)));
        if (avi.value() >= attribute->size() ||
            !attribute->ConvertValue<T>(avi, static_cast<std::int8_t>(components),
                                        values.data() + p * static_cast<std::size_t>(components)))
            return make_error(ErrorCode::ParseError, std::string("Draco attribute ") + name + " value of point " +
                                                         std::to_string(p) + " is out of range");
    }
    return values;
}

//! The point count a Draco point-cloud stream announces, read before Draco allocates for it (its decoder sizes every
//! attribute by that count before reading any value, so a few bytes could ask for gigabytes). The header is "DRACO",
//! major and minor version, encoder type (0: point cloud), encoder method and 16 flag bits; a point cloud's geometry
//! data then starts with its point count as a little-endian int32. Streams with metadata (flag 0x8000) are refused:
//! the count then sits after a variable-length block. Mesh streams (type 1) are left to Draco (their count is in the
//! connectivity data). Empty when the stream is a mesh.
Result<std::optional<std::uint32_t>> announced_point_count(std::span<const std::uint8_t> bytes) {
    constexpr std::size_t kHeader = 11;
    if (bytes.size() < kHeader || std::string_view(reinterpret_cast<const char*>(bytes.data()), 5) != "DRACO")
        return make_error(ErrorCode::ParseError, "Draco data does not start with a Draco header");
    if (bytes[7] != 0) return std::optional<std::uint32_t>{};
    const unsigned flags = bytes[9] | (unsigned(bytes[10]) << 8);
    if (flags & 0x8000u) return make_error(ErrorCode::ParseError, "Draco point clouds with metadata are not read");
    if (bytes.size() < kHeader + 4) return make_error(ErrorCode::ParseError, "Draco point cloud ends in its header");
    const std::uint32_t count = bytes[kHeader] | (std::uint32_t(bytes[kHeader + 1]) << 8) |
                                (std::uint32_t(bytes[kHeader + 2]) << 16) | (std::uint32_t(bytes[kHeader + 3]) << 24);
    if (count > 0x7fffffffu) return make_error(ErrorCode::ParseError, "Draco point cloud has a negative point count");
    return std::optional<std::uint32_t>{count};
}

Result<PointData> decode_unchecked(std::span<const std::uint8_t> bytes, const AttributeIds& ids,
                                   std::size_t max_points) {
    auto announced = announced_point_count(bytes);
    if (!announced) return announced.error();
    if (*announced && **announced > max_points)
        return make_error(ErrorCode::BudgetExceeded, "Draco point cloud announces " + std::to_string(**announced) +
                                                         " points, more than the limit of " +
                                                         std::to_string(max_points));
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    draco::Decoder decoder;
    auto decoded = decoder.DecodePointCloudFromBuffer(&buffer);
    if (!decoded.ok())
        return make_error(ErrorCode::ParseError, std::string("Draco decoder failed: ") + decoded.status().error_msg());
    const std::unique_ptr<draco::PointCloud> cloud = std::move(decoded).value();
    if (!cloud) return make_error(ErrorCode::ParseError, "Draco data holds no point cloud");
    if (cloud->num_points() > max_points)
        return make_error(ErrorCode::BudgetExceeded, "Draco point cloud has " + std::to_string(cloud->num_points()) +
                                                         " points, more than the limit of " +
                                                         std::to_string(max_points));
    if (ids.position < 0) return make_error(ErrorCode::ParseError, "no POSITION attribute");
    PointData out;
    auto positions = extract<float>(*cloud, ids.position, 3, "POSITION");
    if (!positions) return positions.error();
    out.positions = std::move(*positions);
    if (ids.normal >= 0) {
        auto normals = extract<float>(*cloud, ids.normal, 3, "NORMAL");
        if (!normals) return normals.error();
        out.normals = std::move(*normals);
    }
    if (ids.color >= 0) {
        const draco::PointAttribute* attribute = cloud->GetAttributeByUniqueId(static_cast<std::uint32_t>(ids.color));
        out.color_components = attribute ? attribute->num_components() : 3;
        if (out.color_components != 3 && out.color_components != 4)
            return make_error(ErrorCode::ParseError,
                              "Draco COLOR attribute has " + std::to_string(out.color_components) + " components");
        auto colors = extract<float>(*cloud, ids.color, out.color_components, "COLOR_0");
        if (!colors) return colors.error();
        out.colors = std::move(*colors);
    }
    return out;
}

}  // namespace

Result<Encoded> encode(const PointData& points, const draco_codec::EncodeOptions& options) {
    try {
        return encode_unchecked(points, options);
    } catch (const std::bad_alloc&) {
        return make_error(ErrorCode::BudgetExceeded, "out of memory while Draco-encoding the point cloud");
    } catch (const std::exception&) {
        return make_error(ErrorCode::Internal, "Draco encoder failed");
    }
}

Result<PointData> decode(std::span<const std::uint8_t> bytes, const AttributeIds& ids, std::size_t max_points) {
    try {
        return decode_unchecked(bytes, ids, max_points);
    } catch (const std::bad_alloc&) {
        return make_error(ErrorCode::BudgetExceeded, "out of memory while decoding Draco data");
    } catch (const std::exception&) {
        return make_error(ErrorCode::ParseError, "Draco decoder failed: the data is not a Draco stream we can read");
    }
}

}  // namespace surfaced::draco_points
