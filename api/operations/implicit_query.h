// POST /implicit/query: questions asked of an implicit scene, answered in JSON.
//
// Request (application/json; "scene" and at least one of "points" / "rays" required):
//   {"scene": {...},                            a scene node (api/scene_codec.h)
//    "points": [[x, y, z], ...],                classified and evaluated
//    "tolerance": t,                            >= 0 (default 1e-6): |f| <= t is "on"
//    "rays": [{"origin": [..], "direction": [..]}, ...],   direction non-zero (normalised)
//    "max_distance": d,                         > 0 (default 100): farthest t searched along each ray
//    "max_steps": n}                            1 .. Limits::max_ray_steps (default min(1000, that))
// Response: {"kind": "exact_distance" | "distance_bound" | "general", "lipschitz": L,
//            "points": [{"class": "inside" | "on" | "outside" | "undefined", "value": f, "gradient": [..]}],
//            "rays": [{"hit": true, "t": t, "point": [..], "normal": [..], "steps": n} | {"hit": false, "steps": n}]}
// Values that are undefined (NaN from an expression) are null. Errors: problem+json with field paths
// ("points[3][1]", "rays[0].direction", "scene.args[1].radius"); 422 budget_exceeded when points + rays exceed
// Limits::max_query_points or max_steps exceeds Limits::max_ray_steps, checked before the scene is evaluated;
// 503 when the compute deadline passes.
#pragma once

#include "api/operation.h"

namespace surfaced::api::operations {

ApiResponse implicit_query(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
