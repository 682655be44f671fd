// Checks on a glTF file's JSON before tinygltf reads it (gltf_internal.hpp): its nesting, the
// lengths of its top-level arrays, its required extensions, URIs, the buffer-view ranges of its
// images, and the GLB container.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "gltf_internal.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/scene/gltf.hpp"

namespace leanfade::scene::gltf_detail {

using json = nlohmann::json;

namespace {

// ---------------------------------------------------------------------------------------------
// Checks on the JSON before tinygltf reads it: URIs, and the ranges tinygltf itself trusts when
// it hands an image's buffer view to the image callback.

std::uint64_t json_uint(const json& object, const char* key, std::uint64_t fallback,
                        const std::string& where) {
    const auto it = object.find(key);
    if (it == object.end()) return fallback;
    if (!it->is_number_unsigned())
        throw std::runtime_error(where + ": '" + key + "' is not a non-negative integer");
    return it->get<std::uint64_t>();
}

}  // namespace

// The images that some material's texture names (through `textures`): its normal, occlusion,
// emissive, base colour, metallic-roughness and KHR_materials_anisotropy textures.
std::vector<bool> images_used_by_materials(const json& root) {
    const auto images = root.find("images");
    std::vector<bool> used(images != root.end() && images->is_array() ? images->size() : 0, false);
    const auto textures = root.find("textures");
    const auto materials = root.find("materials");
    if (textures == root.end() || !textures->is_array() || materials == root.end() ||
        !materials->is_array())
        return used;
    const auto mark = [&](const json& info) {
        if (!info.is_object()) return;
        const auto index = info.find("index");
        if (index == info.end() || !index->is_number_unsigned()) return;
        const auto t = index->get<std::uint64_t>();
        if (t >= textures->size() || !(*textures)[t].is_object()) return;
        const auto source = (*textures)[t].find("source");
        if (source == (*textures)[t].end() || !source->is_number_unsigned()) return;
        const auto i = source->get<std::uint64_t>();
        if (i < used.size()) used[i] = true;
    };
    for (const json& material : *materials) {
        if (!material.is_object()) continue;
        for (const char* key : {"normalTexture", "occlusionTexture", "emissiveTexture"})
            if (const auto texture = material.find(key); texture != material.end()) mark(*texture);
        if (const auto extensions = material.find("extensions");
            extensions != material.end() && extensions->is_object())
            if (const auto anisotropy = extensions->find(kGltfAnisotropyExtension);
                anisotropy != extensions->end() && anisotropy->is_object())
                if (const auto texture = anisotropy->find("anisotropyTexture");
                    texture != anisotropy->end())
                    mark(*texture);
        if (const auto pbr = material.find("pbrMetallicRoughness");
            pbr != material.end() && pbr->is_object())
        {
            if (const auto base = pbr->find("baseColorTexture"); base != pbr->end()) mark(*base);
            if (const auto mr = pbr->find("metallicRoughnessTexture"); mr != pbr->end()) mark(*mr);
        }
    }
    return used;
}

// The nesting depth of the JSON text, without recursion (tinygltf converts `extras` and
// `extensions` to its values recursively: a file nested some 20000 levels deep overflowed the
// stack). Strings are skipped with their escapes; the text is not otherwise validated here.
void check_json_depth(const std::string& text) {
    int depth = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\')
                ++i;
            else if (c == '"')
                in_string = false;
            continue;
        }
        if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxGltfJsonDepth)
                throw std::runtime_error("the JSON nests deeper than " +
                                         std::to_string(kMaxGltfJsonDepth) +
                                         " levels of arrays and objects");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

void check_json(const json& root, bool external_allowed) {
    if (!root.is_object()) throw std::runtime_error("the JSON is not an object");
    if (const auto required = root.find("extensionsRequired"); required != root.end()) {
        if (!required->is_array()) throw std::runtime_error("'extensionsRequired' is not an array");
        for (const json& name : *required) {
            if (!name.is_string())
                throw std::runtime_error("'extensionsRequired' holds a value that is not a name");
            const std::string extension = name.get<std::string>();
            if (std::find(kSupportedGltfExtensions.begin(), kSupportedGltfExtensions.end(),
                          extension) == kSupportedGltfExtensions.end())
                throw std::runtime_error("requires the extension '" + escape_text(extension) +
                                         "' (extensionsRequired), which leanfade does not "
                                         "support");
        }
    }
    for (const GltfArrayLimit& limit : kGltfArrayLimits) {
        const auto it = root.find(limit.key);
        if (it != root.end() && it->is_array() && it->size() > limit.max_elements)
            throw std::runtime_error("'" + std::string(limit.key) + "' has " +
                                     std::to_string(it->size()) + " elements, more than the " +
                                     "limit of " + std::to_string(limit.max_elements));
    }
    if (const auto meshes = root.find("meshes"); meshes != root.end() && meshes->is_array())
        for (std::size_t m = 0; m < meshes->size(); ++m) {
            const json& mesh = (*meshes)[m];
            if (!mesh.is_object()) continue;
            const auto primitives = mesh.find("primitives");
            if (primitives != mesh.end() && primitives->is_array() &&
                primitives->size() > kMaxGltfPrimitivesPerMesh)
                throw std::runtime_error("mesh " + std::to_string(m) + " has " +
                                         std::to_string(primitives->size()) +
                                         " primitives, more than the limit of " +
                                         std::to_string(kMaxGltfPrimitivesPerMesh));
        }
    auto array = [&](const char* key) -> const json* {
        const auto it = root.find(key);
        if (it == root.end()) return nullptr;
        if (!it->is_array()) throw std::runtime_error(std::string("'") + key + "' is not an array");
        return &*it;
    };
    const json* buffers = array("buffers");
    const json* views = array("bufferViews");
    const json* images = array("images");
    auto check_uri = [&](const json& object, const std::string& where) {
        const auto it = object.find("uri");
        if (it == object.end()) return;
        if (!it->is_string()) throw std::runtime_error(where + ": 'uri' is not a string");
        const std::string uri = it->get<std::string>();
        const std::string refusal = uri_refusal(uri, external_allowed);
        if (!refusal.empty())
            throw std::runtime_error(where + ": URI '" + escape_text(uri) + "' " + refusal);
    };
    if (buffers != nullptr)
        for (std::size_t i = 0; i < buffers->size(); ++i) {
            if (!(*buffers)[i].is_object())
                throw std::runtime_error("buffer " + std::to_string(i) + " is not an object");
            check_uri((*buffers)[i], "buffer " + std::to_string(i));
        }
    if (images == nullptr) return;
    for (std::size_t i = 0; i < images->size(); ++i) {
        const json& image = (*images)[i];
        const std::string where = "image " + std::to_string(i);
        if (!image.is_object()) throw std::runtime_error(where + " is not an object");
        check_uri(image, where);
        if (!image.contains("bufferView")) continue;
        const std::uint64_t v = json_uint(image, "bufferView", 0, where);
        if (views == nullptr || v >= views->size() || !(*views)[v].is_object())
            throw std::runtime_error(where + ": buffer view " + std::to_string(v) +
                                     " does not exist");
        const json& view = (*views)[v];
        const std::string view_name = "buffer view " + std::to_string(v);
        const std::uint64_t b = json_uint(view, "buffer", ~std::uint64_t(0), view_name);
        if (buffers == nullptr || b >= buffers->size())
            throw std::runtime_error(view_name + ": its buffer does not exist");
        const std::uint64_t offset = json_uint(view, "byteOffset", 0, view_name);
        const std::uint64_t length = json_uint(view, "byteLength", 0, view_name);
        const std::uint64_t buffer_length =
            json_uint((*buffers)[b], "byteLength", 0, "buffer " + std::to_string(b));
        if (length == 0 || offset > buffer_length || length > buffer_length - offset)
            throw std::runtime_error(view_name + " (bytes " + std::to_string(offset) + " + " +
                                     std::to_string(length) + ") lies outside buffer " +
                                     std::to_string(b) + " (" + std::to_string(buffer_length) +
                                     " bytes)");
    }
}

// The GLB container (glTF 2.0 §4.4): checked here completely, since tinygltf 2.7 reads up to 8
// bytes past a binary chunk whose length is at the end of the file. Returns the JSON chunk.
std::string glb_json_chunk(const std::vector<std::uint8_t>& bytes) {
    auto u32 = [&](std::size_t at) {
        return std::uint32_t(bytes[at]) | std::uint32_t(bytes[at + 1]) << 8 |
               std::uint32_t(bytes[at + 2]) << 16 | std::uint32_t(bytes[at + 3]) << 24;
    };
    if (bytes.size() < 20) throw std::runtime_error("GLB file shorter than its 20-byte header");
    if (u32(4) != 2)
        throw std::runtime_error("GLB version " + std::to_string(u32(4)) + " (expected 2)");
    const std::uint64_t length = u32(8);
    if (length != bytes.size())
        throw std::runtime_error("GLB header says " + std::to_string(length) +
                                 " bytes, the file has " + std::to_string(bytes.size()));
    const std::uint64_t json_length = u32(12);
    if (u32(16) != 0x4E4F534Au) throw std::runtime_error("the first GLB chunk is not JSON");
    if (json_length == 0 || 20 + json_length > length)
        throw std::runtime_error("the GLB JSON chunk (" + std::to_string(json_length) +
                                 " bytes) does not fit in the file");
    std::uint64_t at = 20 + ((json_length + 3) / 4) * 4;
    if (at < length) {
        if (at + 8 > length) throw std::runtime_error("truncated GLB chunk header");
        const std::uint64_t chunk_length = u32(std::size_t(at));
        if (u32(std::size_t(at) + 4) != 0x004E4942u)
            throw std::runtime_error("the second GLB chunk is not BIN");
        if (chunk_length > length - at - 8)
            throw std::runtime_error("the GLB BIN chunk (" + std::to_string(chunk_length) +
                                     " bytes) does not fit in the file");
    }
    return std::string(reinterpret_cast<const char*>(bytes.data()) + 20, std::size_t(json_length));
}

}  // namespace leanfade::scene::gltf_detail
