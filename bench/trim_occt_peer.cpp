// OpenCASCADE 7.6 peer of bench_trim: the trimmed NURBS face built from the same data, meshed by BRepMesh.
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepLib.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Precision.hxx>
#include <ShapeFix_Face.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array1OfPnt2d.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_FormatVersion.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <chrono>
#include <sstream>
#include <string>
#include <vector>

#include "bench/trim_peers.h"
#include "tests/support/occt_nurbs.h"

namespace surfaced::bench {
namespace {

Handle(Geom2d_BSplineCurve) make_curve(const TrimCurve& c) {
    const int n = static_cast<int>(c.points.size());
    TColgp_Array1OfPnt2d poles(1, n);
    TColStd_Array1OfReal weights(1, n);
    for (int i = 0; i < n; ++i) {
        poles.SetValue(i + 1,
                       gp_Pnt2d(c.points[static_cast<std::size_t>(i)].x, c.points[static_cast<std::size_t>(i)].y));
        weights.SetValue(i + 1, c.weights.empty() ? 1.0 : c.weights[static_cast<std::size_t>(i)]);
    }
    TColStd_Array1OfReal k(1, 1);
    TColStd_Array1OfInteger m(1, 1);
    testing::occt_knots(c.knots, k, m);
    return new Geom2d_BSplineCurve(poles, weights, k, m, c.degree);
}

}  // namespace

PeerMesh occt_mesh(const TrimmedSurface& trimmed, double deflection, int runs) {
    PeerMesh out;
    Handle(Geom_BSplineSurface) surface = testing::to_occt_surface(trimmed.surface);
    BRepBuilderAPI_MakeFace natural(surface, Precision::Confusion());
    if (!natural.IsDone()) {
        out.error = "natural face";
        return out;
    }
    BRepBuilderAPI_MakeFace maker(natural.Face());
    for (const TrimLoop& hole : trimmed.holes) {
        BRepBuilderAPI_MakeWire wire;
        for (const TrimCurve& c : hole.curves) wire.Add(BRepBuilderAPI_MakeEdge(make_curve(c), surface).Edge());
        maker.Add(wire.Wire());
    }
    TopoDS_Face face = maker.Face();
    BRepLib::BuildCurves3d(face);
    ShapeFix_Face fix(face);  // orients the hole wires
    fix.Perform();
    face = fix.Face();
    for (int r = 0; r < runs; ++r) {
        BRepTools::Clean(face);
        const auto t0 = std::chrono::steady_clock::now();
        BRepMesh_IncrementalMesh mesher(face, deflection, false, 0.5, false);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        out.ms = r == 0 ? ms : std::min(out.ms, ms);
    }
    // Debian's OCCT 7.6.3 lacks NCollection_AliasedArray.hxx, which Poly_Triangulation.hxx includes: the triangles
    // are read back from the face written in the BRep text format (version 2, with its triangulation) instead.
    std::ostringstream text;
    BRepTools::Write(face, text, Standard_True, Standard_False, TopTools_FormatVersion_VERSION_2);
    std::istringstream in(text.str());
    std::string word;
    while (in >> word && word != "Triangulations") {}
    int count = 0;
    if (!(in >> count) || count < 1) {
        out.error = "no triangulation";
        return out;
    }
    int nodes = 0, triangles = 0, has_uv = 0;
    double deflection_used = 0;
    in >> nodes >> triangles >> has_uv >> deflection_used;
    for (int i = 0; i < nodes; ++i) {
        Vec3 p;
        in >> p.x >> p.y >> p.z;
        out.mesh.positions.push_back(p);
    }
    for (int i = 0; has_uv && i < 2 * nodes; ++i) in >> deflection_used;
    for (int i = 0; i < triangles; ++i) {
        int a = 0, b = 0, c = 0;
        in >> a >> b >> c;
        out.mesh.add_face({static_cast<Index>(a - 1), static_cast<Index>(b - 1), static_cast<Index>(c - 1)});
    }
    if (!in) out.error = "unreadable triangulation";
    return out;
}

double occt_evaluate(const BSplineSurface& surface, const std::vector<double>& uv, int order, double& checksum) {
    Handle(Geom_BSplineSurface) s = testing::to_occt_surface(surface);
    double sum = 0;
    const auto t0 = std::chrono::steady_clock::now();
    gp_Pnt p;
    gp_Vec du, dv, duu, dvv, duv;
    for (std::size_t k = 0; k + 1 < uv.size(); k += 2) {
        if (order == 0) {
            s->D0(uv[k], uv[k + 1], p);
        } else if (order == 1) {
            s->D1(uv[k], uv[k + 1], p, du, dv);
            sum += du.X() + dv.Y();
        } else {
            s->D2(uv[k], uv[k + 1], p, du, dv, duu, dvv, duv);
            sum += du.X() + dv.Y() + duu.Z() + duv.X() + dvv.Y();
        }
        sum += p.X() + p.Y() + p.Z();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    checksum += sum;
    return seconds;
}

}  // namespace surfaced::bench
