#pragma once
// Small glTF 2.0 files written by the tests: meshes, materials, PNG images and nodes, stored as
// a .gltf with external .bin and image files, a .gltf with everything in data: URIs, or a .glb.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "leanfade/test/scratch.hpp"

namespace leanfade::scene::test {

// An empty folder LEANFADE_TEST_TMP/<suite>/<name> for one test's files (removed first).
using leanfade::test::fresh_scratch_folder;
inline std::filesystem::path fresh_test_folder(const std::string& suite, const std::string& name) {
    return fresh_scratch_folder(suite, name);
}

struct GltfTestPrimitive {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;   // empty: no NORMAL
    std::vector<glm::vec2> uvs;       // glTF convention (v down); empty: no TEXCOORD_0
    std::vector<glm::vec2> uvs1;      // glTF convention (v down); empty: no TEXCOORD_1
    std::vector<glm::vec4> tangents;  // empty: no TANGENT
    std::vector<std::uint32_t> indices;  // empty: not indexed
    int material = -1;
    int mode = 4;  // TRIANGLES
};

struct GltfTestMaterial {
    std::string name;
    glm::vec4 base_color{1.0f};
    int base_color_image = -1;  // index into images (one texture per image)
    int normal_image = -1;
    float normal_scale = 1.0f;
    std::optional<float> roughness{};   // roughnessFactor; none: not written (1 by glTF)
    std::optional<float> metallic{};    // metallicFactor; none: not written (1 by glTF)
    int metallic_roughness_image = -1;  // metallicRoughnessTexture
    std::string alpha_mode{};           // alphaMode; empty: not written (OPAQUE)
    float alpha_cutoff = 0.5f;          // alphaCutoff, written with alphaMode MASK
    bool double_sided = false;          // doubleSided (written when true)
    nlohmann::json base_color_transform{};  // KHR_texture_transform of baseColorTexture, or null
    // Merged into the material's JSON last (an RFC 7386 merge patch: occlusionTexture,
    // emissiveFactor, extensions, ...), or null.
    nlohmann::json patch{};
};

struct GltfTestNode {
    int mesh = -1;
    std::vector<int> children;
    std::vector<double> matrix;       // 16 values, column-major, or empty
    std::vector<double> translation;  // 3 values or empty
    std::vector<double> scale;        // 3 values or empty
};

struct GltfTestFile {
    std::vector<std::vector<GltfTestPrimitive>> meshes;
    std::vector<GltfTestMaterial> materials;
    std::vector<std::vector<std::uint8_t>> images;  // encoded PNG bytes
    std::vector<GltfTestNode> nodes;                // empty: one node per mesh
    nlohmann::json patch{};  // merged into the file's JSON last (extensionsUsed, ...), or null
};

enum class GltfStorage { External, Embedded, Binary };

// The glTF JSON and its one binary buffer (every accessor, then the images when not external).
// `external_name`: the stem of the external files (External only).
struct GltfTestOutput {
    nlohmann::json json;
    std::vector<std::uint8_t> bin;
};
GltfTestOutput build_gltf(const GltfTestFile& file, GltfStorage storage,
                          const std::string& external_name);

// Writes `file` at `path` (.gltf or .glb); External also writes `<stem>.bin` and
// `<stem>_image<N>.png` beside it.
void write_gltf(const GltfTestFile& file, const std::string& path, GltfStorage storage);

// A GLB container of `json` and `bin` (glTF 2.0 §4.4), chunks padded to 4 bytes.
std::vector<std::uint8_t> pack_glb(const nlohmann::json& json,
                                   const std::vector<std::uint8_t>& bin);

// Base64 of `bytes` (for data: URIs).
std::string base64(const std::vector<std::uint8_t>& bytes);

// An encoded 8-bit RGB(A) PNG of `channels` channels, `pixel(x, y)` giving values in [0, 1]
// (rows top first).
std::vector<std::uint8_t> png_bytes(int width, int height, int channels,
                                    const std::vector<float>& pixels);

// Two triangles of the unit square in the xy plane facing +z, uv = (x, 1 - y) in glTF's
// convention (so leanfade's v = y), with normals and without tangents.
GltfTestPrimitive unit_quad(int material = -1);

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes);
std::vector<std::uint8_t> read_bytes(const std::string& path);

}  // namespace leanfade::scene::test
