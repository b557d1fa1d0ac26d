// Invariant for the API codecs: an error is a 4xx problem with a detail, never a 5xx (an internal error is a bug).
#pragma once

#include "api/errors.h"
#include "fuzz/fuzz_check.h"

namespace surfaced::fuzz {

template <class T>
void check_api_result(const api::ApiResult<T>& result) {
    if (result.ok()) return;
    const api::ApiError& error = result.error();
    if (error.status < 400 || error.status >= 500)
        fail("API codec answered a non-4xx error", error.code + ": " + error.detail);
    if (error.detail.empty()) fail("API codec error", "empty detail for " + error.code);
}

}  // namespace surfaced::fuzz
