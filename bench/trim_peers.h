// The trimmed-surface bench's peer: OpenCASCADE's BRepMesh on the same trimmed NURBS face. Its headers compile in
// trim_occt_peer.cpp only.
#pragma once

#include <string>

#include "geometry/mesh/polygon_mesh.h"
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

}  // namespace surfaced::bench
