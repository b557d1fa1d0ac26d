// Embree 3 as the ray peer of bench_spatial_peers: its single-ray path, rtcIntersect1. Embree's headers compile here
// only.
#include <embree3/rtcore.h>

#include <limits>

#include "bench/spatial_peers.h"

namespace surfaced::bench {

struct EmbreeScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
};

EmbreeScene::EmbreeScene(const std::vector<double>& positions, const std::vector<unsigned>& triangles)
    : impl_(std::make_unique<Impl>()) {
    impl_->device = rtcNewDevice("threads=1");
    if (!impl_->device) {
        error = "rtcNewDevice failed";
        return;
    }
    impl_->scene = rtcNewScene(impl_->device);
    RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    const std::size_t vertices = positions.size() / 3, count = triangles.size() / 3;
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices));
    auto* index = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count));
    if (!v || !index) {
        error = "rtcSetNewGeometryBuffer failed";
        rtcReleaseGeometry(geometry);
        return;
    }
    for (std::size_t i = 0; i < positions.size(); ++i) v[i] = static_cast<float>(positions[i]);
    for (std::size_t i = 0; i < triangles.size(); ++i) index[i] = triangles[i];
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(impl_->scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(impl_->scene);
    if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE) error = "Embree reported an error building the scene";
}

EmbreeScene::~EmbreeScene() {
    if (impl_->scene) rtcReleaseScene(impl_->scene);
    if (impl_->device) rtcReleaseDevice(impl_->device);
}

void EmbreeScene::first_hits(const std::vector<double>& rays, std::vector<double>& t) const {
    t.assign(rays.size() / 6, -1.0);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::size_t i = 0; i < t.size(); ++i) {
        const double* r = &rays[6 * i];
        RTCRayHit hit{};
        hit.ray.org_x = static_cast<float>(r[0]);
        hit.ray.org_y = static_cast<float>(r[1]);
        hit.ray.org_z = static_cast<float>(r[2]);
        hit.ray.dir_x = static_cast<float>(r[3]);
        hit.ray.dir_y = static_cast<float>(r[4]);
        hit.ray.dir_z = static_cast<float>(r[5]);
        hit.ray.tnear = 0.0f;
        hit.ray.tfar = std::numeric_limits<float>::infinity();
        hit.ray.mask = 0xffffffffu;
        hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(impl_->scene, &context, &hit);
        if (hit.hit.geomID != RTC_INVALID_GEOMETRY_ID) t[i] = hit.ray.tfar;
    }
}

std::string embree_version() { return RTC_VERSION_STRING; }

}  // namespace surfaced::bench
