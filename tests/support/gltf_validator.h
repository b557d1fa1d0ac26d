// Runs the Khronos glTF validator (npm gltf-validator, installed under tests/node_modules by scripts/test.sh)
// on GLB bytes. Used by every test that produces a GLB.
#pragma once

#include <string>
#include <string_view>

namespace surfaced::testing {

struct GltfValidation {
    bool ran = false;  //!< false when node or the validator could not be run (the test must fail then)
    int errors = 0;
    int warnings = 0;
    int infos = 0;
    std::string report;  //!< the validator's JSON report, or why it did not run
};

GltfValidation run_gltf_validator(std::string_view glb_bytes);

}  // namespace surfaced::testing
