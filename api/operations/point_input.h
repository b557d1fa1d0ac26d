// What the endpoints that take a point cloud share (POST /pointcloud, POST /reconstruct): the media types they read,
// the JSON members "points", "normals", "colors", reading an uploaded point file, and normal estimation behind its
// budget. One copy, so both endpoints read the same clouds and word the same mistakes alike.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "api/errors.h"
#include "api/limits.h"
#include "api/operations/request_forms.h"
#include "geometry/core/cancel.h"
#include "geometry/io/pointcloud_io.h"
#include "geometry/pointcloud/point_cloud.h"

namespace surfaced::api::operations {

//! For 415 messages: the media types a point endpoint reads.
inline constexpr std::string_view kPointMediaTypes =
    "application/json, application/ply, model/obj, text/x-xyz, model/gltf-binary, model/gltf+json, "
    "application/octet-stream or text/plain (sniffed), "
    "multipart/form-data (one file part, options as fields)";

//! The file types a point endpoint reads (for the file part of a form).
bool reads_point_media_type(std::string_view media_type);

//! A GeoError about point i names "points[i]" (or `array`[i]) in a JSON request (the mesh mapping in geometry_error
//! would say mesh.positions).
ApiError point_error(const GeoError& error, Source source, const char* array = "points");

//! "points", "normals", "colors" of a JSON body: at most limits.max_points points (422 budget_exceeded naming
//! "points"), normals one per point, colours [r, g, b(, a)] in 0..1. Normals are normalised and a zero one is an
//! error, unless `keep_normal_lengths` (the lengths are then the samples' confidence; zero drops a sample).
ApiResult<PointCloud> decode_json_points(const nlohmann::json& root, const Limits& limits,
                                         bool keep_normal_lengths = false);

//! The point format of an uploaded body: from its media type, sniffed for application/octet-stream and text/plain;
//! 415 unsupported_media_type otherwise.
ApiResult<PointFormat> uploaded_point_format(std::string_view media_type, std::string_view body);
//! The uploaded file read with limits.max_points as the reader's limit (errors carry its line or offset). glTF gives
//! the vertices of its POINTS primitives, or, without any, those of its triangle primitives (gltf_points.h).
ApiResult<PointCloud> read_uploaded_points(std::string_view body, PointFormat format, const Limits& limits);

//! Estimates and orients the cloud's normals with k neighbours (geometry/pointcloud/normals.h), after the budget on
//! points x k (the kNN graph orientation keeps): over limits.max_points x 16 is 422 budget_exceeded naming
//! `k_field`. An error of the estimation names the point (JSON), else `estimate_field` when given (too few points).
std::optional<ApiError> estimate_point_normals(PointCloud& cloud, std::int64_t k, const Limits& limits,
                                               const Cancel& cancel, Source source, const std::string& k_field,
                                               std::optional<std::string> estimate_field);

}  // namespace surfaced::api::operations
