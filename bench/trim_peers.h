// The trimmed-surface bench's peer: OpenCASCADE's BRepMesh on the same trimmed NURBS face. Its headers compile in
// trim_occt_peer.cpp only.
#pragma once

#include <string>
#include <vector>

#include "geometry/mesh/polygon_mesh.h"
#include "geometry/surfaces/bspline_surface.h"
#include "geometry/surfaces/trim_loops.h"

namespace surfaced::bench {

struct PeerMesh {
    PolygonMesh mesh;  //!< triangles; positions only
    double ms = 0;     //!< best time of BRepMesh_IncrementalMesh over the runs
    std::string error;
};

//! The face of `trimmed` (a Geom_BSplineSurface, its holes as wires of Geom2d_BSplineCurve pcurves; no outer loops)
//! meshed by BRepMesh_IncrementalMesh with linear deflection `deflection` (angular deflection 0.5, the default),
//! best of `runs` runs.
PeerMesh occt_mesh(const TrimmedSurface& trimmed, double deflection, int runs);

//! Evaluates `surface` as an OCCT Geom_BSplineSurface at the (u, v) pairs in `uv` (u0, v0, u1, v1, ...): D0
//! (order 0), D1 (order 1) or D2 (order 2). Returns the seconds of the evaluation loop alone (the surface is built
//! before), and adds every result's coordinates to `checksum` (so nothing is optimised away and the answers can be
//! compared with ours).
double occt_evaluate(const BSplineSurface& surface, const std::vector<double>& uv, int order, double& checksum);

}  // namespace surfaced::bench
