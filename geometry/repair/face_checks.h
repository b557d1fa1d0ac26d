// Per-face tests shared by repair_mesh and audit_mesh: degenerate faces and faces that repeat an earlier one.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/repair/index_table.h"

namespace surfaced::repair_detail {

//! True when the face uses a vertex more than once.
bool has_repeated_index(std::span<const Index> face);

//! True when the face's vector area (Newell: half the sum of the cross products of consecutive corners, taken from
//! the first corner) is exactly zero: collinear or coincident corners.
bool has_zero_area(std::span<const Vec3> positions, std::span<const Index> face);

//! Recognises faces with the same vertex set as a face seen before (in either orientation, any rotation).
class FaceSets {
public:
    explicit FaceSets(std::size_t max_faces) : table_(max_faces) {}
    //! Remembers the face (its vertices, without repeats) and returns true, or returns false when a face with the
    //! same vertex set was remembered before. At most max_faces faces are remembered.
    bool insert(std::span<const Index> face);

private:
    IndexTable table_;
    std::vector<Index> sorted_;       // sorted vertices of the remembered faces, one after another
    std::vector<std::size_t> start_;  // remembered face -> its start in sorted_
    std::vector<Index> scratch_;
};

}  // namespace surfaced::repair_detail
