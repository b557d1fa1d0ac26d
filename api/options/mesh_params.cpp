#include "api/options/mesh_params.h"

namespace surfaced::api::options {

SubdivideParams subdivide_params(const OptionValues& values) {
    SubdivideParams params;
    values.get("scheme", kSchemeNames, params.scheme);
    values.get("levels", params.levels);
    params.levels_given = values.has("levels");
    values.get("tolerance", params.tolerance);
    values.get("straddle", params.straddle);
    values.get("target_faces", params.target_faces);
    values.get("boundary", kBoundaryNames, params.boundary);
    values.get("crease_method", kCreaseMethodNames, params.crease_method);
    values.get("triangle_rule", kTriangleRuleNames, params.triangle_rule);
    values.get("uv_interpolation", kUvInterpolationNames, params.uv_interpolation);
    values.get("loop_weights", kLoopWeightNames, params.loop_weights);
    values.get("limit_surface", params.limit_surface);
    values.get("threads", params.threads);
    values.get_output(params.output);
    params.patches = values.given_as("format", "patches");
    return params;
}

SimplifyParams simplify_params(const OptionValues& values) {
    SimplifyParams params;
    values.get("target_faces", params.target_faces);
    values.get("ratio", params.ratio);
    values.get("max_error", params.max_error);
    values.get("lock_border", params.lock_border);
    values.get("restore_volume", params.restore_volume);
    values.get("threads", params.threads);
    values.get("report_error", params.report_error);
    values.get("locked_vertices", params.locked_vertices);
    values.get("repair", kRepairModeNames, params.repair);
    values.get_output(params.output);
    return params;
}

}  // namespace surfaced::api::options
