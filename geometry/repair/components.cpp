// Component labelling by union-find over joined faces; outward orientation by the sign of each closed component's
// volume, measured from a vertex of the component (so that far-away coordinates do not drown it in rounding).
#include "geometry/repair/components.h"

#include "geometry/repair/disjoint_sets.h"

namespace surfaced::repair_detail {

Components find_components(const CornerTable& table, const std::vector<Index>& partner) {
    const std::size_t faces = table.offsets.size() - 1;
    DisjointSets sets(faces);
    for (Index c = 0; c < table.corner_count(); ++c)
        if (partner[c] != kInvalidIndex && partner[c] > c) sets.unite(table.face(c), table.face(partner[c]));
    Components result;
    result.of_face.resize(faces);
    result.face_count.assign(faces, 0);
    for (Index f = 0; f < faces; ++f) {
        const Index root = sets.find(f);
        result.of_face[f] = root;
        if (result.face_count[root]++ == 0) ++result.count;
    }
    return result;
}

double face_volume(std::span<const Vec3> positions, std::span<const Index> face, const Vec3& origin, bool reversed) {
    const std::size_t n = face.size();
    auto corner = [&](std::size_t j) { return positions[face[reversed && j > 0 ? n - j : j]] - origin; };
    double v = 0;
    const Vec3 a = corner(0);
    for (std::size_t j = 1; j + 1 < n; ++j) v += dot(a, cross(corner(j), corner(j + 1)));
    return v / 6.0;
}

void orient_outward(const CornerTable& table, std::span<const Vec3> positions, const std::vector<Index>& partner,
                    const Components& components, std::vector<std::uint8_t>& flip) {
    const std::size_t faces = table.offsets.size() - 1;
    // the lowest face of a component (the one that names it) keeps its winding; it comes first, so go backwards
    for (Index f = static_cast<Index>(faces); f-- > 0;) flip[f] ^= flip[components.of_face[f]];
    std::vector<std::uint8_t> open(faces, 0);
    for (Index c = 0; c < table.corner_count(); ++c)
        if (partner[c] == kInvalidIndex) open[components.of_face[table.face(c)]] = 1;
    std::vector<double> volume(faces, 0.0);
    for (Index f = 0; f < faces; ++f) {
        const Index root = components.of_face[f];
        if (open[root]) continue;
        const Vec3& origin = positions[table.indices[table.offsets[root]]];
        volume[root] +=
            face_volume(positions, table.indices.subspan(table.offsets[f], table.offsets[f + 1] - table.offsets[f]),
                        origin, flip[f] != 0);
    }
    for (Index f = 0; f < faces; ++f) {
        const Index root = components.of_face[f];
        if (!open[root] && volume[root] < 0) flip[f] ^= 1;
    }
}

}  // namespace surfaced::repair_detail
