// Face-varying data (texture coordinates): OpenSubdiv's face-varying channel (Vtr::FVarLevel) and its
// FVarLinearInterpolation rules. The UVs are refined on a "value mesh" of their own, with the same topology steps,
// point rules and crease rules as positions; what makes them face-varying is the value mesh's starting sharpness
// (seams are its boundaries; the linear modes and OpenSubdiv's value tags make some values corners) and a few values
// whose rule the value mesh cannot express (UvOverride). Internal to geometry/subdivision.
#pragma once

#include <vector>

#include "geometry/core/types.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/subdivision/creases.h"
#include "geometry/subdivision/subdivide.h"
#include "geometry/subdivision/topology.h"

namespace surfaced::subdivision {

//! A "dependent-sharp" value (OpenSubdiv's FVarLevel::ValueTag::_depSharp, corners-plus1/2) follows OpenSubdiv's tags
//! rather than the value mesh's own rule: of the two values at a vertex, the one without semi-sharp edges inside its
//! span stays a corner while its sibling (which has them) is semi-sharp, then becomes a crease with the sibling's
//! fractional weight. `ends` are the value mesh's two edges along which it is a crease (refined with it).
struct UvOverride {
    Index value;
    Index ends[2];
    Index sibling;  //!< the semi-sharp value it depends on
};

//! One face-varying channel (UVs) on its own topology: a "value mesh" with the mesh's faces but a vertex per distinct
//! (vertex, value) pair, so that seams are its boundaries.
struct Channel {
    Level level;               //!< the value mesh
    Sharpness sharp;           //!< its sharpness: the mesh's, plus what the face-varying rules make sharp
    std::vector<Vec3> values;  //!< per value-mesh vertex: (u, v, 0)
    std::vector<UvOverride> overrides;
};

//! The mesh's texture coordinates (mesh.uvs/uv_indices) as a channel of the base level `mesh_level` (sharpness
//! `mesh_sharp`), refined `options.levels` times with `options.uv_interpolation`. `threaded` as for positions.
Channel refine_uvs(const PolygonMesh& mesh, const Level& mesh_level, const Sharpness& mesh_sharp,
                   const SubdivisionOptions& options, bool threaded);

}  // namespace surfaced::subdivision
