#include "api/operations/mesh_repair.h"

#include <cstdint>
#include <cstring>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "api/json_codec.h"

namespace surfaced::api::operations {
namespace {

struct PositionHash {
    std::size_t operator()(const Vec3& p) const noexcept {
        std::uint64_t h = 1469598103934665603ull;
        for (int i = 0; i < 3; ++i) {
            double c = p[i] == 0 ? 0.0 : p[i];  // -0 and +0 are one position
            std::uint64_t bits = 0;
            std::memcpy(&bits, &c, sizeof bits);
            h = (h ^ bits) * 1099511628211ull;
        }
        return static_cast<std::size_t>(h);
    }
};

}  // namespace

ApiError input_error(const GeoError& error, Source source, const ReadReport& read) {
    ApiError out = geometry_error(error, source, read);
    if (error.code == ErrorCode::NonManifold || error.code == ErrorCode::DegenerateFace)
        out.hint = source == Source::Json ? "\"repair\": \"auto\" repairs it" : "repair=auto repairs it";
    return out;
}

std::optional<ApiError> check_manifold_input(const PolygonMesh& mesh, Source source, const ReadReport& read) {
    if (const Status valid = validate(mesh); !valid) return input_error(valid.error(), source, read);
    if (const Status manifold = check_manifold(mesh); !manifold) return input_error(manifold.error(), source, read);
    return std::nullopt;
}

std::vector<Index> vertices_by_position(const PolygonMesh& before, const PolygonMesh& after,
                                        const std::vector<std::int64_t>& vertices) {
    std::unordered_map<Vec3, Index, PositionHash> at;
    at.reserve(after.positions.size());
    for (std::size_t v = after.positions.size(); v-- > 0;) at[after.positions[v]] = static_cast<Index>(v);  // lowest
    std::vector<Index> out;
    out.reserve(vertices.size());
    for (std::int64_t v : vertices) {
        const auto it = at.find(before.positions[static_cast<std::size_t>(v)]);
        out.push_back(it == at.end() ? kInvalidIndex : it->second);
    }
    return out;
}

std::string repairs_header(const RepairReport& report) {
    std::string out;
    for (const auto& [name, count] : repair_counts(report)) {
        if (!out.empty()) out += "; ";
        out += name;
        out += '=';
        out += std::to_string(count);
    }
    return out;
}

}  // namespace surfaced::api::operations
