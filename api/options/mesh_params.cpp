#include "api/options/mesh_params.h"

namespace surfaced::api::options {

SubdivideParams subdivide_params(const OptionValues& values) {
    SubdivideParams params;
    values.get("scheme", kSchemeNames, params.scheme);
    values.get("levels", params.levels);
    params.levels_given = values.has("levels");
    values.get("max_faces", params.max_faces);
    values.get("boundary", kBoundaryNames, params.boundary);
    values.get("crease_method", kCreaseMethodNames, params.crease_method);
    values.get("triangle_rule", kTriangleRuleNames, params.triangle_rule);
    values.get("uv_interpolation", kUvInterpolationNames, params.uv_interpolation);
    values.get("loop_weights", kLoopWeightNames, params.loop_weights);
    values.get("limit_surface", params.limit_surface);
    values.get_output(params.output);
    return params;
}

}  // namespace surfaced::api::options
