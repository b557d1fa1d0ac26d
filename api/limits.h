// Request budgets. Checked in api/ before any geometry work starts (STYLE d.3: never trust input sizes):
// subdivision multiplies the face count by 4 per level, so a 2-face mesh at level 12 is already 33M faces.
// The server fills these from its command line (`surfaced serve --max-body-mb ... --max-output-faces ...`).
#pragma once

#include <cstddef>
#include <cstdint>

namespace surfaced::api {

struct Limits {
    //! Largest request body accepted, in bytes. Over it: 413 payload_too_large (the HTTP layer enforces the same
    //! number with set_payload_max_length, so the body is never buffered in full).
    std::size_t max_body_bytes = std::size_t{64} << 20;
    //! Largest `levels` for subdivision. Over it: 422 budget_exceeded, field "levels".
    int max_levels = 8;
    //! Largest input mesh (after decoding). Over it: 422 budget_exceeded.
    std::uint64_t max_input_faces = 2'000'000;
    std::uint64_t max_input_vertices = 4'000'000;
    //! Largest predicted output (predicted_face_count). Over it: 422 budget_exceeded, before any refinement.
    std::uint64_t max_output_faces = 4'000'000;
    //! Bézier patches (POST /tessellate, GET /patches/...): most patches in one request, and most segments along
    //! one direction of one patch (a tolerance needing more is 422 budget_exceeded, field "tolerance"). The
    //! predicted triangle count is checked against max_output_faces before tessellating.
    std::uint64_t max_patches = 100'000;
    int max_patch_segments = 256;
};

}  // namespace surfaced::api
