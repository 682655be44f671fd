// glTF files for the tests (test_gltf_builder.hpp).
#include "test_gltf_builder.hpp"

#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <unistd.h>

#include "leanfade/core/image.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::scene::test {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// Appends `data` (4-byte aligned) to `bin` as a buffer view + accessor; returns the accessor.
int add_accessor(json& root, std::vector<std::uint8_t>& bin, const void* data, std::size_t bytes,
                 std::size_t count, int component_type, const char* type) {
    while (bin.size() % 4 != 0) bin.push_back(0);
    const std::size_t offset = bin.size();
    bin.resize(offset + bytes);
    std::memcpy(bin.data() + offset, data, bytes);
    root["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    root["accessors"].push_back({{"bufferView", root["bufferViews"].size() - 1},
                                 {"componentType", component_type},
                                 {"count", count},
                                 {"type", type}});
    return int(root["accessors"].size()) - 1;
}

}  // namespace

std::string base64(const std::vector<std::uint8_t>& bytes) {
    static const char* digits =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t a = bytes[i];
        const std::uint32_t b = i + 1 < bytes.size() ? bytes[i + 1] : 0;
        const std::uint32_t c = i + 2 < bytes.size() ? bytes[i + 2] : 0;
        const std::uint32_t v = (a << 16) | (b << 8) | c;
        out += digits[(v >> 18) & 63];
        out += digits[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? digits[v & 63] : '=';
    }
    return out;
}

GltfTestOutput build_gltf(const GltfTestFile& file, GltfStorage storage,
                          const std::string& external_name) {
    GltfTestOutput out;
    json& root = out.json;
    root["asset"] = {{"version", "2.0"}, {"generator", "leanfade tests"}};
    root["bufferViews"] = json::array();
    root["accessors"] = json::array();
    std::vector<std::uint8_t>& bin = out.bin;
    root["meshes"] = json::array();
    for (const auto& mesh : file.meshes) {
        json primitives = json::array();
        for (const GltfTestPrimitive& p : mesh) {
            json prim;
            prim["attributes"]["POSITION"] = add_accessor(
                root, bin, p.positions.data(), p.positions.size() * 12, p.positions.size(), 5126,
                "VEC3");
            // The bounds glTF 2.0 requires of POSITION accessors (§3.6.2.4).
            if (!p.positions.empty()) {
                glm::vec3 lo(p.positions[0]), hi(p.positions[0]);
                for (const glm::vec3& v : p.positions) {
                    lo = glm::min(lo, v);
                    hi = glm::max(hi, v);
                }
                json& accessor = root["accessors"][prim["attributes"]["POSITION"].get<std::size_t>()];
                accessor["min"] = {lo.x, lo.y, lo.z};
                accessor["max"] = {hi.x, hi.y, hi.z};
            }
            if (!p.normals.empty())
                prim["attributes"]["NORMAL"] = add_accessor(
                    root, bin, p.normals.data(), p.normals.size() * 12, p.normals.size(), 5126,
                    "VEC3");
            if (!p.uvs.empty())
                prim["attributes"]["TEXCOORD_0"] =
                    add_accessor(root, bin, p.uvs.data(), p.uvs.size() * 8, p.uvs.size(), 5126,
                                 "VEC2");
            if (!p.uvs1.empty())
                prim["attributes"]["TEXCOORD_1"] = add_accessor(
                    root, bin, p.uvs1.data(), p.uvs1.size() * 8, p.uvs1.size(), 5126, "VEC2");
            if (!p.tangents.empty())
                prim["attributes"]["TANGENT"] = add_accessor(
                    root, bin, p.tangents.data(), p.tangents.size() * 16, p.tangents.size(), 5126,
                    "VEC4");
            if (!p.indices.empty())
                prim["indices"] = add_accessor(root, bin, p.indices.data(), p.indices.size() * 4,
                                               p.indices.size(), 5125, "SCALAR");
            if (p.material >= 0) prim["material"] = p.material;
            if (p.mode != 4) prim["mode"] = p.mode;
            primitives.push_back(prim);
        }
        root["meshes"].push_back({{"primitives", primitives}});
    }
    if (!file.materials.empty()) {
        root["materials"] = json::array();
        for (const GltfTestMaterial& m : file.materials) {
            json material;
            material["name"] = m.name;
            material["pbrMetallicRoughness"]["baseColorFactor"] = {m.base_color.r, m.base_color.g,
                                                                   m.base_color.b, m.base_color.a};
            if (m.base_color_image >= 0)
                material["pbrMetallicRoughness"]["baseColorTexture"] = {
                    {"index", m.base_color_image}};
            if (m.base_color_image >= 0 && !m.base_color_transform.is_null())
                material["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
                    {"KHR_texture_transform", m.base_color_transform}};
            if (m.normal_image >= 0)
                material["normalTexture"] = {{"index", m.normal_image}, {"scale", m.normal_scale}};
            if (m.roughness) material["pbrMetallicRoughness"]["roughnessFactor"] = *m.roughness;
            if (m.metallic) material["pbrMetallicRoughness"]["metallicFactor"] = *m.metallic;
            if (m.metallic_roughness_image >= 0)
                material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {
                    {"index", m.metallic_roughness_image}};
            if (!m.alpha_mode.empty()) material["alphaMode"] = m.alpha_mode;
            if (m.alpha_mode == "MASK") material["alphaCutoff"] = m.alpha_cutoff;
            if (m.double_sided) material["doubleSided"] = true;
            if (!m.patch.is_null()) material.merge_patch(m.patch);
            root["materials"].push_back(material);
        }
    }
    if (!file.images.empty()) {
        root["images"] = json::array();
        root["textures"] = json::array();
        for (std::size_t i = 0; i < file.images.size(); ++i) {
            const std::vector<std::uint8_t>& png = file.images[i];
            json image;
            if (storage == GltfStorage::External) {
                image["uri"] = external_name + "_image" + std::to_string(i) + ".png";
            } else if (storage == GltfStorage::Embedded) {
                image["uri"] = "data:image/png;base64," + base64(png);
            } else {
                while (bin.size() % 4 != 0) bin.push_back(0);
                root["bufferViews"].push_back(
                    {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", png.size()}});
                bin.insert(bin.end(), png.begin(), png.end());
                image["bufferView"] = root["bufferViews"].size() - 1;
                image["mimeType"] = "image/png";
            }
            root["images"].push_back(image);
            root["textures"].push_back({{"source", i}});
        }
    }
    root["nodes"] = json::array();
    if (file.nodes.empty()) {
        for (std::size_t m = 0; m < file.meshes.size(); ++m) root["nodes"].push_back({{"mesh", m}});
    } else {
        for (const GltfTestNode& n : file.nodes) {
            json node = json::object();
            if (n.mesh >= 0) node["mesh"] = n.mesh;
            if (!n.children.empty()) node["children"] = n.children;
            if (!n.matrix.empty()) node["matrix"] = n.matrix;
            if (!n.translation.empty()) node["translation"] = n.translation;
            if (!n.scale.empty()) node["scale"] = n.scale;
            root["nodes"].push_back(node);
        }
    }
    // Scene 0: the nodes that are nobody's child.
    std::vector<bool> child(root["nodes"].size(), false);
    for (const GltfTestNode& n : file.nodes)
        for (int c : n.children) child[std::size_t(c)] = true;
    json roots = json::array();
    for (std::size_t i = 0; i < child.size(); ++i)
        if (!child[i]) roots.push_back(i);
    root["scenes"] = json::array({{{"nodes", roots}}});
    root["scene"] = 0;
    while (bin.size() % 4 != 0) bin.push_back(0);
    json buffer = {{"byteLength", bin.size()}};
    if (storage == GltfStorage::External) buffer["uri"] = external_name + ".bin";
    if (storage == GltfStorage::Embedded)
        buffer["uri"] = "data:application/octet-stream;base64," + base64(bin);
    root["buffers"] = json::array({buffer});
    if (!file.patch.is_null()) root.merge_patch(file.patch);
    return out;
}

std::vector<std::uint8_t> pack_glb(const json& json_value, const std::vector<std::uint8_t>& bin) {
    std::string text = json_value.dump();
    while (text.size() % 4 != 0) text += ' ';
    std::vector<std::uint8_t> padded = bin;
    while (padded.size() % 4 != 0) padded.push_back(0);
    std::vector<std::uint8_t> out;
    auto u32 = [&](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) out.push_back(std::uint8_t(v >> (8 * i)));
    };
    const std::size_t total = 12 + 8 + text.size() + (padded.empty() ? 0 : 8 + padded.size());
    out.reserve(total);
    for (char c : {'g', 'l', 'T', 'F'}) out.push_back(std::uint8_t(c));
    u32(2);
    u32(std::uint32_t(total));
    u32(std::uint32_t(text.size()));
    u32(0x4E4F534Au);  // JSON
    out.insert(out.end(), text.begin(), text.end());
    if (!padded.empty()) {
        u32(std::uint32_t(padded.size()));
        u32(0x004E4942u);  // BIN
        out.insert(out.end(), padded.begin(), padded.end());
    }
    return out;
}

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + path);
}

std::vector<std::uint8_t> read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read " + path);
    return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

void write_gltf(const GltfTestFile& file, const std::string& path, GltfStorage storage) {
    const fs::path p(path);
    const std::string stem = p.stem().string();
    const GltfTestOutput out = build_gltf(file, storage, stem);
    if (storage == GltfStorage::Binary) {
        write_bytes(path, pack_glb(out.json, out.bin));
        return;
    }
    const std::string text = out.json.dump(1);
    write_bytes(path, std::vector<std::uint8_t>(text.begin(), text.end()));
    if (storage == GltfStorage::External) {
        write_bytes((p.parent_path() / (stem + ".bin")).string(), out.bin);
        for (std::size_t i = 0; i < file.images.size(); ++i)
            write_bytes((p.parent_path() / (stem + "_image" + std::to_string(i) + ".png")).string(),
                        file.images[i]);
    }
}

std::vector<std::uint8_t> png_bytes(int width, int height, int channels,
                                    const std::vector<float>& pixels) {
    static std::atomic<int> counter{0};
    Image image(width, height, channels);
    image.pixels = pixels;
    const fs::path path = fs::path(LEANFADE_TEST_TMP) /
                          ("gltf_png_" + std::to_string(::getpid()) + "_" +
                           std::to_string(counter++) + ".png");
    io::write_png(path.string(), image, 8);
    std::vector<std::uint8_t> bytes = read_bytes(path.string());
    fs::remove(path);
    return bytes;
}

GltfTestPrimitive unit_quad(int material) {
    GltfTestPrimitive p;
    p.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    p.normals.assign(4, glm::vec3(0, 0, 1));
    for (const glm::vec3& q : p.positions) p.uvs.push_back(glm::vec2(q.x, 1.0f - q.y));
    p.indices = {0, 1, 2, 0, 2, 3};
    p.material = material;
    return p;
}

}  // namespace leanfade::scene::test
