// The only TU that includes Draco's headers. Draco reports problems through draco::Status, but it allocates with
// plain new/vector, so std::bad_alloc (and anything else) is caught here and turned into a GeoError: nothing may
// escape into the public API.
#include "geometry/io/draco_codec.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <new>

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

namespace surfaced::draco_codec {

namespace {

//! Adds a float attribute with one value per point (identity mapping: glTF attributes are per vertex).
int add_float_attribute(draco::Mesh& mesh, draco::GeometryAttribute::Type type, int components,
                        const std::vector<float>& values) {
    draco::GeometryAttribute layout;
    layout.Init(type, nullptr, static_cast<std::uint8_t>(components), draco::DT_FLOAT32, false,
                static_cast<std::int64_t>(sizeof(float)) * components, 0);
    const std::size_t count = values.size() / static_cast<std::size_t>(components);
    const int att_id = mesh.AddAttribute(layout, true, static_cast<std::uint32_t>(count));
    draco::PointAttribute* attribute = mesh.attribute(att_id);
    for (std::size_t i = 0; i < count; ++i)
        attribute->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(i)),
                                     values.data() + i * static_cast<std::size_t>(components));
    return att_id;
}

//! Adds colours (0..1 floats, clamped) as a normalised unsigned-byte attribute, one value per point.
int add_color_attribute(draco::Mesh& mesh, int components, const std::vector<float>& values) {
    draco::GeometryAttribute layout;
    layout.Init(draco::GeometryAttribute::COLOR, nullptr, static_cast<std::uint8_t>(components), draco::DT_UINT8, true,
                components, 0);
    const std::size_t count = values.size() / static_cast<std::size_t>(components);
    const int att_id = mesh.AddAttribute(layout, true, static_cast<std::uint32_t>(count));
    draco::PointAttribute* attribute = mesh.attribute(att_id);
    std::uint8_t value[4] = {0, 0, 0, 0};
    for (std::size_t i = 0; i < count; ++i) {
        for (int k = 0; k < components; ++k) {
            const float c = values[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(k)];
            value[k] = static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f));
        }
        attribute->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(i)), value);
    }
    return att_id;
}

Result<Encoded> encode_unchecked(const MeshData& data, const EncodeOptions& options) {
    if (Status quantizable = check_quantizable_positions(data.positions); !quantizable)
        return std::move(quantizable.error());
    const std::size_t points = data.point_count();
    draco::Mesh mesh;
    mesh.set_num_points(static_cast<std::uint32_t>(points));
    mesh.SetNumFaces(data.triangle_count());
    for (std::size_t t = 0; t < data.triangle_count(); ++t) {
        draco::Mesh::Face face;
        for (int k = 0; k < 3; ++k) face[k] = draco::PointIndex(data.indices[3 * t + static_cast<std::size_t>(k)]);
        mesh.SetFace(draco::FaceIndex(static_cast<std::uint32_t>(t)), face);
    }

    Encoded out;
    const int position_att = add_float_attribute(mesh, draco::GeometryAttribute::POSITION, 3, data.positions);
    const int normal_att =
        data.normals.empty() ? -1 : add_float_attribute(mesh, draco::GeometryAttribute::NORMAL, 3, data.normals);
    const int texcoord_att =
        data.texcoords.empty() ? -1 : add_float_attribute(mesh, draco::GeometryAttribute::TEX_COORD, 2, data.texcoords);
    const int color_att = data.colors.empty() ? -1 : add_color_attribute(mesh, data.color_components, data.colors);
    // The glTF extension refers to attributes by Draco's unique id, which survives encoding (attribute slots may not).
    out.ids.position = static_cast<int>(mesh.attribute(position_att)->unique_id());
    if (normal_att >= 0) out.ids.normal = static_cast<int>(mesh.attribute(normal_att)->unique_id());
    if (texcoord_att >= 0) out.ids.texcoord = static_cast<int>(mesh.attribute(texcoord_att)->unique_id());
    if (color_att >= 0) out.ids.color = static_cast<int>(mesh.attribute(color_att)->unique_id());

    draco::Encoder encoder;
    encoder.SetSpeedOptions(options.encode_speed, options.decode_speed);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, options.quantize_position);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, options.quantize_normal);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, options.quantize_texcoord);
    draco::EncoderBuffer buffer;
    const draco::Status status = encoder.EncodeMeshToBuffer(mesh, &buffer);
    if (!status.ok())
        return make_error(ErrorCode::Internal, std::string("Draco encoder failed: ") + status.error_msg());
    out.bytes.assign(buffer.data(), buffer.size());
    return out;
}

//! Copies one attribute of the decoded mesh as `components` floats per point, checking every mapping.
Result<std::vector<float>> extract(const draco::Mesh& mesh, int unique_id, int components, const char* name) {
    const draco::PointAttribute* attribute = mesh.GetAttributeByUniqueId(static_cast<std::uint32_t>(unique_id));
    if (attribute == nullptr)
        return make_error(ErrorCode::ParseError, std::string("Draco data has no attribute with id ") +
                                                     std::to_string(unique_id) + " (" + name + ")");
    if (attribute->num_components() != components)
        return make_error(ErrorCode::ParseError, std::string("Draco attribute ") + name + " has " +
                                                     std::to_string(attribute->num_components()) +
                                                     " components, expected " + std::to_string(components));
    const std::size_t points = mesh.num_points();
    if (!attribute->is_mapping_identity() && attribute->indices_map_size() < points)
        return make_error(ErrorCode::ParseError, std::string("Draco attribute ") + name + " does not map every point");
    std::vector<float> values(points * static_cast<std::size_t>(components));
    for (std::size_t p = 0; p < points; ++p) {
        const draco::AttributeValueIndex avi =
            attribute->mapped_index(draco::PointIndex(static_cast<std::uint32_t>(p)));
        if (avi.value() >= attribute->size() ||
            !attribute->ConvertValue<float>(avi, static_cast<std::int8_t>(components),
                                            values.data() + p * static_cast<std::size_t>(components)))
            return make_error(ErrorCode::ParseError, std::string("Draco attribute ") + name + " value of point " +
                                                         std::to_string(p) + " is out of range");
    }
    return values;
}

//! A little-endian uint32 at `at`, advancing it.
bool read_u32(std::span<const std::uint8_t> bytes, std::size_t& at, std::uint32_t& out) {
    if (bytes.size() - at < 4) return false;
    out = bytes[at] | (std::uint32_t(bytes[at + 1]) << 8) | (std::uint32_t(bytes[at + 2]) << 16) |
          (std::uint32_t(bytes[at + 3]) << 24);
    at += 4;
    return true;
}

//! A Draco varint (7 bits per byte, low first, at most 5 bytes for 32 bits) at `at`, advancing it.
bool read_varint(std::span<const std::uint8_t> bytes, std::size_t& at, std::uint32_t& out) {
    std::uint64_t value = 0;
    for (int shift = 0; shift < 35; shift += 7) {
        if (at >= bytes.size()) return false;
        const std::uint8_t byte = bytes[at++];
        value |= std::uint64_t(byte & 0x7f) << shift;
        if (!(byte & 0x80)) {
            if (value > 0xffffffffu) return false;
            out = std::uint32_t(value);
            return true;
        }
    }
    return false;
}

Result<MeshData> decode_unchecked(std::span<const std::uint8_t> bytes, const AttributeIds& ids,
                                  const DecodeLimits& limits) {
    auto announced = announced_mesh_counts(bytes);
    if (!announced) return announced.error();
    if (announced->faces > limits.max_triangles)
        return make_error(ErrorCode::BudgetExceeded, "Draco mesh announces " + std::to_string(announced->faces) +
                                                         " triangles, more than the limit of " +
                                                         std::to_string(limits.max_triangles));
    if (announced->points > limits.max_points)
        return make_error(ErrorCode::BudgetExceeded, "Draco mesh announces " + std::to_string(announced->points) +
                                                         " vertices, more than the limit of " +
                                                         std::to_string(limits.max_points));
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok())
        return make_error(ErrorCode::ParseError, std::string("Draco decoder failed: ") + decoded.status().error_msg());
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    if (!mesh) return make_error(ErrorCode::ParseError, "Draco data does not hold a triangle mesh");

    const std::size_t points = mesh->num_points();
    const std::size_t faces = mesh->num_faces();
    if (points > limits.max_points)
        return make_error(ErrorCode::BudgetExceeded, "Draco mesh has " + std::to_string(points) +
                                                         " vertices, more than the limit of " +
                                                         std::to_string(limits.max_points));
    if (faces > limits.max_triangles)
        return make_error(ErrorCode::BudgetExceeded, "Draco mesh has " + std::to_string(faces) +
                                                         " triangles, more than the limit of " +
                                                         std::to_string(limits.max_triangles));

    MeshData out;
    out.indices.resize(faces * 3);
    for (std::size_t f = 0; f < faces; ++f) {
        const draco::Mesh::Face& face = mesh->face(draco::FaceIndex(static_cast<std::uint32_t>(f)));
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = face[k].value();
            if (v >= points)
                return make_error(ErrorCode::ParseError, "Draco triangle " + std::to_string(f) + " refers to point " +
                                                             std::to_string(v) + " of " + std::to_string(points));
            out.indices[3 * f + static_cast<std::size_t>(k)] = v;
        }
    }
    if (ids.position < 0) return make_error(ErrorCode::ParseError, "Draco primitive has no POSITION attribute");
    auto positions = extract(*mesh, ids.position, 3, "POSITION");
    if (!positions) return positions.error();
    out.positions = std::move(*positions);
    if (ids.normal >= 0) {
        auto normals = extract(*mesh, ids.normal, 3, "NORMAL");
        if (!normals) return normals.error();
        out.normals = std::move(*normals);
    }
    if (ids.texcoord >= 0) {
        auto texcoords = extract(*mesh, ids.texcoord, 2, "TEXCOORD_0");
        if (!texcoords) return texcoords.error();
        out.texcoords = std::move(*texcoords);
    }
    if (ids.color >= 0) {
        const draco::PointAttribute* attribute = mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(ids.color));
        out.color_components = attribute ? attribute->num_components() : 3;
        if (out.color_components != 3 && out.color_components != 4)
            return make_error(ErrorCode::ParseError,
                              "Draco COLOR_0 attribute has " + std::to_string(out.color_components) + " components");
        auto colors = extract(*mesh, ids.color, out.color_components, "COLOR_0");
        if (!colors) return colors.error();
        out.colors = std::move(*colors);
    }
    return out;
}

}  // namespace

Status check_quantizable_positions(const std::vector<float>& positions) {
    for (int axis = 0; axis < 3; ++axis) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (std::size_t i = static_cast<std::size_t>(axis); i < positions.size(); i += 3) {
            lo = std::min(lo, static_cast<double>(positions[i]));
            hi = std::max(hi, static_cast<double>(positions[i]));
        }
        if (hi - lo > static_cast<double>(std::numeric_limits<float>::max())) {
            char extent[32];
            std::snprintf(extent, sizeof extent, "%.9g", hi - lo);
            return make_error(ErrorCode::InvalidArgument,
                              std::string("the positions span ") + extent + " along " + "xyz"[axis] +
                                  ", beyond the float32 range that Draco compression quantizes over; use "
                                  "compression none");
        }
    }
    return Ok{};
}

Result<Encoded> encode(const MeshData& mesh, const EncodeOptions& options) {
    try {
        return encode_unchecked(mesh, options);
    } catch (const std::bad_alloc&) {
        return make_error(ErrorCode::BudgetExceeded, "out of memory while Draco-encoding the mesh");
    } catch (const std::exception&) {
        return make_error(ErrorCode::Internal, "Draco encoder failed");
    }
}

Result<AnnouncedCounts> announced_mesh_counts(std::span<const std::uint8_t> bytes) {
    constexpr std::size_t kHeader = 11;
    if (bytes.size() < kHeader || std::string_view(reinterpret_cast<const char*>(bytes.data()), 5) != "DRACO")
        return make_error(ErrorCode::ParseError, "Draco data does not start with a Draco header");
    const unsigned version = (unsigned(bytes[5]) << 8) | bytes[6];
    if (bytes[7] != 1) return make_error(ErrorCode::ParseError, "Draco data does not hold a triangle mesh");
    const unsigned flags = bytes[9] | (unsigned(bytes[10]) << 8);
    if (flags & 0x8000u) return make_error(ErrorCode::ParseError, "Draco meshes with metadata are not read");
    const auto ends = [] { return make_error(ErrorCode::ParseError, "Draco mesh ends in its connectivity header"); };
    // counts are uint32 before bitstream 2.0 (sequential: 2.2), varints from then on
    const auto count = [&](std::size_t& at, std::uint32_t& out, unsigned varint_from) {
        return version < varint_from ? read_u32(bytes, at, out) : read_varint(bytes, at, out);
    };
    std::size_t at = kHeader;
    AnnouncedCounts out;
    if (bytes[8] == 0) {  // sequential: faces, points
        if (!count(at, out.faces, 0x0202) || !count(at, out.points, 0x0202)) return ends();
    } else if (bytes[8] == 1) {  // edgebreaker: traversal type, [new vertices before 2.2], vertices, faces
        std::uint32_t ignored = 0;
        if (at >= bytes.size()) return ends();
        ++at;
        if (version < 0x0202 && !count(at, ignored, 0x0200)) return ends();
        if (!count(at, out.points, 0x0200) || !count(at, out.faces, 0x0200)) return ends();
    } else {
        return make_error(ErrorCode::ParseError,
                          "Draco mesh has an unknown encoding method " + std::to_string(bytes[8]));
    }
    return out;
}

Result<MeshData> decode(std::span<const std::uint8_t> bytes, const AttributeIds& ids, const DecodeLimits& limits) {
    try {
        return decode_unchecked(bytes, ids, limits);
    } catch (const std::bad_alloc&) {
        return make_error(ErrorCode::BudgetExceeded, "out of memory while decoding Draco data");
    } catch (const std::exception&) {
        return make_error(ErrorCode::ParseError, "Draco decoder failed: the data is not a Draco stream we can read");
    }
}

}  // namespace surfaced::draco_codec
