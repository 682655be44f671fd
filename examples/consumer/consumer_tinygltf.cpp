// A program that compiles its own tinygltf (with its file system callbacks, where leanfade's copy
// has none) and links leanfade::scene, which reads glTF files with a tinygltf of its own: both
// copies live in one program without duplicate definitions, and each keeps its configuration
// (leanfade's symbols outside namespace leanfade are local: docs/integration.md, "Linking").
// Built by examples/consumer/CMakeLists.txt; run by the test `package.InstallAndConsume`
// (tests/package).
//
// Usage: consumer_tinygltf OUTPUT_FOLDER   (writes OUTPUT_FOLDER/triangle.gltf). Exit 0 when every
// check holds, 1 with a message naming the first that does not.
// The C library's and the JSON headers come first: tiny_gltf.h includes nlohmann/json.hpp under
// `#pragma GCC visibility push(hidden)`.
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#include <tiny_gltf.h>

#include <leanfade/core/error.hpp>
#include <leanfade/scene/gltf.hpp>

namespace {

int failures = 0;

void check(bool condition, const std::string& what) {
    if (!condition) {
        std::fprintf(stderr, "consumer_tinygltf: FAILED: %s\n", what.c_str());
        ++failures;
    }
}

// One triangle, its three positions in an embedded buffer.
const char* const kTriangle = R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "buffers": [{"byteLength": 36,
               "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]
})";

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: consumer_tinygltf OUTPUT_FOLDER\n");
        return 2;
    }
    const std::string file = std::string(argv[1]) + "/triangle.gltf";
    std::ofstream(file, std::ios::binary) << kTriangle;

    // The program's tinygltf: reads the file through its own file system callbacks.
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string error;
    std::string warning;
    const bool loaded = loader.LoadASCIIFromFile(&model, &error, &warning, file);
    check(loaded, "the program's tinygltf reads " + file + ": " + error);
    check(model.meshes.size() == 1 && model.accessors.size() == 1,
          "the program's tinygltf finds one mesh and one accessor");

    // leanfade's: from the file and from memory.
    try {
        const leanfade::scene::GltfScene scene = leanfade::scene::load_gltf(file);
        check(scene.objects.size() == 1, "leanfade reads one object");
        check(!scene.objects.empty() && scene.objects[0].mesh.vertices.size() == 3,
              "leanfade reads the triangle's three vertices");
        const std::vector<std::uint8_t> bytes(kTriangle, kTriangle + std::string(kTriangle).size());
        const leanfade::scene::GltfScene from_memory =
            leanfade::scene::load_gltf_from_memory(bytes, "triangle.gltf");
        check(from_memory.objects.size() == 1, "leanfade reads one object from memory");
    } catch (const leanfade::Error& e) {
        check(false, std::string("leanfade: ") + e.what());
    }

    if (failures > 0) return 1;
    std::printf("consumer_tinygltf: the program's tinygltf and leanfade's read %s\n", file.c_str());
    return 0;
}
