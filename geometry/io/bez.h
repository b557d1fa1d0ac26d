// Geomview Bézier patch files (.bez / .bbp) and the built-in patch samples (the Utah teapot).
//
// Format (geomview manual, "BBP and BEZ"): a header keyword `[ST]BBP` or `[C]BEZ<Nu><Nv><Nd>[_ST]` -- Nu, Nv the
// degrees in u and v (single digits 1..6), Nd the coordinates per control point (3, or 4 for rational patches);
// BBP = BEZ333 -- followed by any number of patches, each (Nu+1)*(Nv+1) control points with u varying fastest,
// then 4 corner (s, t) pairs when ST is given, then 4 corner RGBA colours when C is given. `#` starts a comment.
//
// Conventions we chose (geomview's own documentation does not spell them out): with Nd = 4 each control point is
// homogeneous (x, y, z, w) as geomview's HPoint3 everywhere else, i.e. already multiplied by its weight: the
// Euclidean control point is (x, y, z) / w and w its weight (w > 0). The 4 (s, t) pairs belong to the corners in
// the order they appear in the control net: (u, v) = (0, 0), (1, 0), (0, 1), (1, 1).
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

#include "geometry/core/result.h"
#include "geometry/surfaces/bezier_patch.h"

namespace surfaced {

struct BezReadOptions {
    std::size_t max_patches = 1'000'000;
};

//! Reads every patch of a BEZ/BBP text. A header keyword may also reappear before any patch to change the patch
//! type for the patches after it (geomview files may mix types). Corner texture coordinates are read
//! into BezierPatch::corner_uvs (tessellation interpolates them bilinearly as the output UVs); colours are read
//! (and checked to be numbers) but not kept. Nd = 4 patches become rational patches (BezierPatch::weights).
//! Errors (with the 1-based line in GeoError::line and the message): ParseError (no or unknown header, a token that
//! is not a number, a patch cut short, no patches), NonFinite, InvalidArgument (a weight <= 0, weights more than
//! kMaxWeightRatio apart), BudgetExceeded (more than max_patches).
Result<PatchSet> read_bez(std::string_view text, const BezReadOptions& options = {});

//! Names of the built-in patch samples ("teapot").
std::span<const std::string_view> patch_sample_names();
//! The BEZ text of a built-in sample, compiled into the binary; empty for an unknown name.
std::string_view patch_sample_text(std::string_view name);

}  // namespace surfaced
