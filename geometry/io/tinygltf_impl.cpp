// The only TU that compiles tinygltf's implementation (and nlohmann/json with it). We compile it ourselves instead
// of linking Debian's libtinygltf.so: libdraco.so exports its own older copy of the tinygltf symbols, and the two
// would bind to each other at run time. See tinygltf_config.h for the configuration.
#include <fstream>  // tinygltf 2.7.0 uses std::ofstream in its writers but only includes <fstream> without NO_FS

#define TINYGLTF_IMPLEMENTATION
#include "geometry/io/tinygltf_config.h"
