// Deciding which faces stay joined across each edge, and which faces to reverse so that joined faces agree.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/repair/mesh_edges.h"

namespace surfaced::repair_detail {

struct Gluing {
    //! Per corner: the corner whose half-edge is joined to this corner's half-edge (the same undirected edge, the
    //! opposite direction once `flip` is applied), or kInvalidIndex where the face is on its own (boundary or cut).
    std::vector<Index> partner;
    //! Per face: 1 to reverse the face. The lowest face of every joined set keeps its winding.
    std::vector<std::uint8_t> flip;
};

//! Joins faces pairwise across edges, at most two faces per edge. Edges used by two faces are joined first (with
//! `orient`, whatever their directions, unless the faces are already tied to each other with the opposite relative
//! winding: a Moebius band or Klein bottle is cut there); without `orient`, only two faces traversing the edge in
//! opposite directions are joined. Edges used by more than two faces come second: their faces are taken in order,
//! each joined to the first still unjoined face of the edge it can agree with (any face of another set, whose set is
//! then reversed as needed; a face of its own set only with the opposite direction); the rest stay unjoined.
Gluing glue_faces(const CornerTable& table, const EdgeGroups& edges, bool orient);

}  // namespace surfaced::repair_detail
