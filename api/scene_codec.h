// Scene JSON -> implicit::Field (internal to api/; includes nlohmann through json_util.h, so only api TUs include it).
//
// A scene is a DAG of nested nodes `{"op": ..., ...}`. Any node may carry `"id": "name"`; `{"ref": "name"}` reuses
// that node (the same Field object is shared, never copied). Every problem is a 400/422 naming the field path
// (`scene.args[1].arg.radius`); expression syntax errors add the 0-based character offset in the detail.
// Budgets (Limits::max_scene_nodes, max_expression_nodes/depth, max_fractal_iterations, max_level_set_samples) are
// checked while parsing, before anything is evaluated; the triangles and vertices of all mesh nodes together
// (max_input_faces, max_input_vertices) before any mesh is decoded. The ops and their members are listed in scene_codec.cpp and
// in api/openapi.json (schema ImplicitScene).
#pragma once

#include <memory>
#include <string>

#include "api/json_util.h"
#include "api/limits.h"
#include "geometry/core/cancel.h"
#include "geometry/core/types.h"
#include "geometry/implicit/field.h"

namespace surfaced::api {

//! Parses a scene node (the value of the request's "scene" member); errors name paths under `path`. `cancel` is
//! polled while mesh nodes index their triangles (the one costly step of building a scene): 503 when it fires.
ApiResult<std::shared_ptr<const implicit::Field>> parse_scene(const json::Json& node, const Limits& limits,
                                                              const std::string& path = "scene",
                                                              const Cancel& cancel = {});
//! "bounds": [[xmin,ymin,zmin],[xmax,ymax,zmax]] with min < max on every axis.
ApiResult<Box3> parse_bounds(const json::Json& value, const std::string& path = "bounds");

}  // namespace surfaced::api
