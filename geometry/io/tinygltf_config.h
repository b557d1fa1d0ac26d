// Internal to geo_gltf: the one way to include tiny_gltf.h (used by the writer only; gltf_read.cpp explains why
// reading does not use it). The configuration macros change the TinyGLTF class's default member initialisers
// (image loader/writer, file-system callbacks), so every TU must see the same ones or the class would differ
// between TUs (an ODR violation). tinygltf_impl.cpp adds TINYGLTF_IMPLEMENTATION on top.
//
//  - no stb_image / stb_image_write: we never decode or write textures;
//  - no external images and no file system: a library inside a server has no business touching files;
//  - no TINYGLTF_ENABLE_DRACO: Draco is encoded and decoded by draco_codec.cpp.
// Debian's tiny_gltf.h finds JSON as <nlohmann/json.hpp> (nlohmann-json3-dev), in the implementation TU only.
#pragma once

#ifndef TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE
#endif
#ifndef TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#endif
#ifndef TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#endif
#ifndef TINYGLTF_NO_FS
#define TINYGLTF_NO_FS
#endif

#include <tiny_gltf.h>
