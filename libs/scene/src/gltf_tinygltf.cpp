// tinygltf's implementation, compiled once, as gltf_internal.hpp configures it (no image decoder,
// no file system access).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#define TINYGLTF_IMPLEMENTATION
#include "gltf_internal.hpp"
