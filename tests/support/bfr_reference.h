// OpenSubdiv Bfr as the reference for limit evaluation: a Bfr::Surface per face of one mesh (approximation levels at
// their maximum), evaluated at (face, u, v) with first and second derivatives. Tests only.
#pragma once

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <memory>
#include <vector>

#include "geometry/mesh/polygon_mesh.h"
#include "geometry/subdivision/subdivide.h"
#include "tests/support/osd_reference.h"

namespace surfaced::testing {

//! Bfr's deepest approximation: Far's maximum isolation level.
inline constexpr int kBfrApproxLevel = 10;

struct BfrSample {
    Vec3 p, du, dv, duu, duv, dvv;
};

//! Bfr::Surface for every face of one mesh.
class BfrReference {
public:
    BfrReference(const PolygonMesh& mesh, const SubdivisionOptions& options) : refiner_(make_refiner(mesh, options)) {
        for (const Vec3& p : mesh.positions) points_.insert(points_.end(), {p.x, p.y, p.z});
        OpenSubdiv::Bfr::SurfaceFactory::Options fo;
        fo.SetApproxLevelSmooth(kBfrApproxLevel);
        fo.SetApproxLevelSharp(kBfrApproxLevel);
        factory_ = std::make_unique<OpenSubdiv::Bfr::RefinerSurfaceFactory<>>(*refiner_, fo);
    }
    //! False when Bfr has no limit surface for the face (holes).
    bool evaluate(std::size_t face, double u, double v, BfrSample& out) {
        OpenSubdiv::Bfr::Surface<double> surface;
        if (!factory_->InitVertexSurface(static_cast<int>(face), &surface)) return false;
        std::vector<double> patch(3 * static_cast<std::size_t>(surface.GetNumPatchPoints()));
        surface.PreparePatchPoints(points_.data(), 3, patch.data(), 3);
        const double uv[2] = {u, v};
        double p[3], du[3], dv[3], duu[3], duv[3], dvv[3];
        surface.Evaluate(uv, patch.data(), 3, p, du, dv, duu, duv, dvv);
        out = {{p[0], p[1], p[2]},       {du[0], du[1], du[2]},    {dv[0], dv[1], dv[2]},
               {duu[0], duu[1], duu[2]}, {duv[0], duv[1], duv[2]}, {dvv[0], dvv[1], dvv[2]}};
        return true;
    }

private:
    std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> refiner_;
    std::unique_ptr<OpenSubdiv::Bfr::RefinerSurfaceFactory<>> factory_;
    std::vector<double> points_;
};

}  // namespace surfaced::testing
