// glTF writer for polylines: check -> float positions of every polyline in one buffer view -> one accessor (with
// byteOffset) and one LINE_STRIP primitive per polyline -> tinygltf model -> GLB or embedded glTF.
// Conventions as in gltf_write.cpp: one 4-byte-aligned buffer whose byteLength equals the BIN chunk, POSITION min/max
// taken from the float values actually written (the validator compares them exactly).
#include "geometry/io/polyline_gltf.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "geometry/io/gltf_model.h"

namespace surfaced {
namespace {

Status check(const std::vector<Polyline>& polylines) {
    if (polylines.empty()) return make_error(ErrorCode::InvalidArgument, "no polylines to write to glTF");
    constexpr double kFloatMax = std::numeric_limits<float>::max();
    for (std::size_t i = 0; i < polylines.size(); ++i) {
        const Polyline& line = polylines[i];
        if (line.size() < 2)
            return make_error(ErrorCode::InvalidArgument, "polyline " + std::to_string(i) + " has " +
                                                              std::to_string(line.size()) +
                                                              " point(s); a glTF line strip needs at least 2");
        if (line.size() >= std::numeric_limits<std::uint32_t>::max() - 1)
            return make_error(ErrorCode::BudgetExceeded, "polyline " + std::to_string(i) + " is too long for glTF");
        for (const Vec3& p : line)
            for (int k = 0; k < 3; ++k)
                if (!std::isfinite(p[k]) || std::fabs(p[k]) > kFloatMax)
                    return make_error(ErrorCode::NonFinite,
                                      "polyline " + std::to_string(i) + " has a coordinate that is not a finite float");
    }
    return Ok{};
}

tinygltf::Model build_model(const std::vector<Polyline>& polylines) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "surfaced";
    model.buffers.emplace_back();
    auto& data = model.buffers[0].data;

    std::size_t total = 0;
    for (const Polyline& line : polylines) total += line.size();
    std::vector<float> values;
    values.reserve(total * 3);
    tinygltf::Mesh mesh;
    for (const Polyline& line : polylines) {
        tinygltf::Accessor accessor;
        accessor.bufferView = 0;
        accessor.byteOffset = values.size() * sizeof(float);
        accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
        accessor.type = TINYGLTF_TYPE_VEC3;
        accessor.count = line.size();
        accessor.minValues.assign(3, std::numeric_limits<double>::infinity());
        accessor.maxValues.assign(3, -std::numeric_limits<double>::infinity());
        for (const Vec3& p : line)
            for (int k = 0; k < 3; ++k) {
                const float v = static_cast<float>(p[k]);
                values.push_back(v);
                const auto c = static_cast<std::size_t>(k);
                accessor.minValues[c] = std::min(accessor.minValues[c], static_cast<double>(v));
                accessor.maxValues[c] = std::max(accessor.maxValues[c], static_cast<double>(v));
            }
        model.accessors.push_back(std::move(accessor));

        tinygltf::Primitive primitive;
        primitive.mode = TINYGLTF_MODE_LINE_STRIP;  // non-indexed: vertices are drawn in order
        primitive.attributes["POSITION"] = static_cast<int>(model.accessors.size() - 1);
        mesh.primitives.push_back(std::move(primitive));
    }
    const auto* first = reinterpret_cast<const unsigned char*>(values.data());
    data.assign(first, first + values.size() * sizeof(float));  // floats: already a multiple of 4 bytes

    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = 0;
    view.byteLength = data.size();
    view.byteStride = 3 * sizeof(float);  // shared by several accessors: the validator wants the stride stated
    view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
    model.bufferViews.push_back(std::move(view));

    gltf_detail::add_single_mesh_scene(model, std::move(mesh));
    return model;
}

Result<std::string> write_unchecked(const std::vector<Polyline>& polylines, bool binary) {
    if (Status s = check(polylines); !s) return s.error();
    std::size_t total = 0;
    for (const Polyline& line : polylines) total += line.size();
    // GLB lengths are uint32; leave 1 MiB for the JSON chunk (one accessor and primitive per polyline).
    if (total > (std::numeric_limits<std::uint32_t>::max() - (std::size_t{1} << 20)) / (3 * sizeof(float)))
        return make_error(ErrorCode::BudgetExceeded,
                          "polylines too large for glTF: " + std::to_string(total) + " points");
    tinygltf::Model model = build_model(polylines);
    // text: the buffer is embedded as a base64 data URI, so the .gltf is self-contained
    return gltf_detail::serialise(model, binary);
}

Result<std::string> write_guarded(const std::vector<Polyline>& polylines, bool binary) {
    return gltf_detail::guarded([&] { return write_unchecked(polylines, binary); }, "polyline glTF");
}

}  // namespace

Result<std::string> write_polylines_glb(const std::vector<Polyline>& polylines) {
    return write_guarded(polylines, true);
}

Result<std::string> write_polylines_gltf(const std::vector<Polyline>& polylines) {
    return write_guarded(polylines, false);
}

}  // namespace surfaced
