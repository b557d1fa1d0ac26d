// Polylines (tessellated curves) as glTF 2.0: one scene / node / mesh with one LINE_STRIP primitive (mode 3) per
// polyline, each a non-indexed float POSITION accessor with min/max, all in one buffer. No Draco:
// KHR_draco_mesh_compression is defined for triangle (and point) primitives only, so line strips are stored plain.
#pragma once

#include <string>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"

namespace surfaced {

//! One polyline: its points in order (a closed one repeats its first point at the end).
using Polyline = std::vector<Vec3>;

//! GLB bytes. Preconditions checked (InvalidArgument): at least one polyline, each with >= 2 points (glTF's
//! minimum for LINE_STRIP), all coordinates finite and within float range. BudgetExceeded: more than 2^32 - 2
//! points in one polyline or over 4 GiB of data. Passes the Khronos validator with no errors or warnings.
Result<std::string> write_polylines_glb(const std::vector<Polyline>& polylines);

//! The same scene as one self-contained glTF JSON document (the buffer embedded as a base64 data URI).
Result<std::string> write_polylines_gltf(const std::vector<Polyline>& polylines);

}  // namespace surfaced
