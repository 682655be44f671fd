#pragma once
// What the glTF loader's source files share (not installed): tinygltf as leanfade compiles it
// (gltf_tinygltf.cpp holds its implementation), and the checks on a file's JSON before tinygltf
// reads it (gltf_checks.cpp), used by gltf_loader.cpp.
//
// tinygltf is compiled without its image decoder and without its file system access: images are
// kept encoded and external files are read through the loader's confined callbacks. Its header
// includes nlohmann/json.hpp under `#pragma GCC visibility push(hidden)`, which would hide the
// functions first declared there: JSON and the C library come first.
#include <cstdint>
#include <fstream>  // tiny_gltf.h uses std::ofstream without including it
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#define TINYGLTF_NO_FS
#include <tiny_gltf.h>

namespace leanfade::scene::gltf_detail {

// Why an external URI may not be read ("" when it may): leanfade reads only files inside the
// glTF's folder, named by relative paths (gltf_loader.cpp).
std::string uri_refusal(const std::string& uri, bool external_allowed);

// The images that some material's normal or base colour texture names (through `textures`).
std::vector<bool> images_used_by_materials(const nlohmann::json& root);

// Throws std::runtime_error for JSON text nested deeper than the loader's limit (a scan without
// recursion, strings skipped).
void check_json_depth(const std::string& text);

// Throws std::runtime_error for what tinygltf would trust: URIs it may not read, top-level
// arrays longer than their limits, required extensions leanfade does not support, and the
// buffer-view ranges of images.
void check_json(const nlohmann::json& root, bool external_allowed);

// The JSON chunk of a GLB container, checked completely (glTF 2.0 §4.4); throws
// std::runtime_error for a container that is not one.
std::string glb_json_chunk(const std::vector<std::uint8_t>& bytes);

}  // namespace leanfade::scene::gltf_detail
