// Invariants every fuzz target checks besides "no crash, no sanitizer report, no hang": a reader either fails with
// a located, non-empty message or returns a mesh that passes validate(); the API codecs never answer 5xx.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::fuzz {

[[noreturn]] inline void fail(const char* what, const std::string& detail) {
    std::fprintf(stderr, "fuzz invariant violated: %s: %s\n", what, detail.c_str());
    std::abort();
}

//! A reader's result: an error with a message, or a mesh that validate() accepts.
inline void check_mesh_result(const Result<PolygonMesh>& result) {
    if (!result.ok()) {
        if (result.error().message.empty()) fail("reader error", "empty message");
        if (result.error().code == ErrorCode::Internal) fail("reader error is Internal", result.error().message);
        return;
    }
    const Status valid = validate(*result);
    if (!valid.ok()) fail("reader returned a mesh that validate() rejects", valid.error().message);
}

}  // namespace surfaced::fuzz
