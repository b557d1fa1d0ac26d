// Which box test ray casting runs (internal to geometry/spatial and its tests). The 8-wide ray nodes are tested with
// one AVX instruction sequence when the processor has AVX, else as two SSE halves; both give the same bounds. Tests
// switch AVX off to run the SSE path on machines that have AVX.
#pragma once

#include <atomic>

namespace surfaced::spatial_detail {

//! True: never use AVX for rays (the SSE path is used even where AVX is available). For tests; false by default.
extern std::atomic<bool> ray_avx_disabled;

}  // namespace surfaced::spatial_detail
