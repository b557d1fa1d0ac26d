// The Params structs of /subdivide and /simplify (api/dto.h) from their checked option values: shared by the query
// reader of each operation and the JSON decoders of json_codec.cpp.
#pragma once

#include "api/dto.h"
#include "api/options/option_reader.h"

namespace surfaced::api::options {

SubdivideParams subdivide_params(const OptionValues& values);
SimplifyParams simplify_params(const OptionValues& values);

}  // namespace surfaced::api::options
