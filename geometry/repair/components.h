// Connected components of the joined faces, and their outward orientation.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "geometry/repair/mesh_edges.h"

namespace surfaced::repair_detail {

struct Components {
    std::vector<Index> of_face;     //!< component of each face, named by its lowest face
    std::vector<Index> face_count;  //!< faces of the component named c (0 for names not in use)
    std::size_t count = 0;
};

//! Faces joined through `partner` (directly or through other faces) form a component.
Components find_components(const CornerTable& table, const std::vector<Index>& partner);

//! Makes each component's lowest face keep its winding (reversing the whole component when `flip` says otherwise),
//! then reverses every closed component (no unjoined half-edge) whose signed volume, with `flip` applied, is negative.
void orient_outward(const CornerTable& table, std::span<const Vec3> positions, const std::vector<Index>& partner,
                    const Components& components, std::vector<std::uint8_t>& flip);

//! Signed volume of a face as seen from `origin` (divergence theorem, fan triangles): the sum over a closed surface
//! is its enclosed volume, positive when the faces wind counter-clockwise seen from outside. `reversed`: of the face
//! reversed as repair_mesh reverses it (first corner kept), summed exactly as for the reversed face itself, so that a
//! volume measured before the output is built has the same rounding (and sign) as one measured on the output.
double face_volume(std::span<const Vec3> positions, std::span<const Index> face, const Vec3& origin,
                   bool reversed = false);

}  // namespace surfaced::repair_detail
