// A filtered copy of a glTF scene (gltf.hpp, write_filtered_gltf).
#include "leanfade/scene/gltf.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <span>

#include <nlohmann/json.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/detail/basis_universal.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"
#include "leanfade/io/detail/node_tool.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/scene/detail/lean_map_cache.hpp"
#include "leanfade/version.hpp"

namespace leanfade::scene {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::uint32_t kGlbMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kGlbChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kGlbChunkBin = 0x004E4942;   // "BIN\0"
// The largest binary chunk a GLB holds: its length is a 32-bit field, and so is the file's.
constexpr std::size_t kMaxGlbBinBytes = 0xFFFFFF00u;
constexpr std::uint64_t kMaxGltfFileBytes = std::uint64_t(1) << 30;
// A material's bumps count as anisotropic, and get a KHR_materials_anisotropy texture, when the
// slope covariance of the whole map (its 1 x 1 level) has axes this far apart (the larger
// variance over the smaller): a small footprint's covariance is anisotropic by chance even for
// isotropic bumps, the whole map's is not.
constexpr float kAnisotropyThreshold = 1.5f;

std::uint32_t load_u32(const std::string& bytes, std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | std::uint8_t(bytes[at + std::size_t(i)]);
    return v;
}

void append_u32(std::string& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out += char((v >> (8 * i)) & 0xFFu);
}

// The file as its JSON and, for a .glb, its binary chunk (load_gltf has checked the file).
struct Container {
    json root;
    std::string bin;
    bool has_bin = false;
};

Container read_container(const std::string& path) {
    const std::string bytes = read_regular_file(path, kMaxGltfFileBytes, "glTF file");
    Container c;
    std::string text = bytes;
    if (bytes.size() >= 12 && load_u32(bytes, 0) == kGlbMagic) {
        std::size_t at = 12;
        text.clear();
        while (at + 8 <= bytes.size()) {
            const std::uint32_t length = load_u32(bytes, at), type = load_u32(bytes, at + 4);
            if (length > bytes.size() - at - 8) throw Error(path, "a GLB chunk runs past the end");
            if (type == kGlbChunkJson && text.empty()) text = bytes.substr(at + 8, length);
            if (type == kGlbChunkBin && !c.has_bin) {
                c.bin = bytes.substr(at + 8, length);
                c.has_bin = true;
            }
            at += 8 + std::size_t(length);
        }
    }
    try {
        c.root = json::parse(text);
    } catch (const json::exception&) {
        throw Error(path, "not valid glTF JSON");
    }
    if (!c.root.is_object()) throw Error(path, "not a glTF JSON object");
    return c;
}

// A URI for a relative path: unreserved characters and '/' kept, the rest percent-encoded.
std::string uri_of(const fs::path& relative) {
    std::string out;
    for (const char c : relative.generic_string()) {
        const auto u = static_cast<unsigned char>(c);
        if (std::isalnum(u) || c == '-' || c == '_' || c == '.' || c == '~' || c == '/') {
            out += c;
        } else {
            char hex[4];
            std::snprintf(hex, sizeof hex, "%%%02X", u);
            out += hex;
        }
    }
    return out;
}



// An external file of the scene (a buffer or an image named by a URI) that the output needs
// beside it: the output's folder is another, so a copy is written there.
struct CopiedFile {
    std::string source;    // the input's file, as the glTF names it
    std::string resolved;  // the file it is, its links resolved (inside the glTF's folder)
    std::string target;    // its copy's name, beside the output
};

// Each external URI of buffers, images and the LEANFADE_lean_map of a material that this run
// does not filter again (`filtered`: glTF material indices whose map the run writes), for an
// output in `output_folder`: kept when that is the input's folder; otherwise the file is copied
// beside the output (named after the output's stem and the file's own name, each name once) and
// the URI names the copy, so that the output folder holds everything the file names (leanfade,
// as many loaders, reads only inside it). A file that is a symbolic link inside the folder is
// copied from the file it leads to, which must lie inside the folder too.
std::vector<CopiedFile> relocate_external_files(json& root, const std::string& input,
                                                const fs::path& input_folder,
                                                const fs::path& output_folder,
                                                const std::string& stem,
                                                const std::set<int>& filtered) {
    std::vector<CopiedFile> copies;
    if (fs::weakly_canonical(input_folder) == fs::weakly_canonical(output_folder)) return copies;
    std::map<std::string, std::string> copied;  // source -> copy's name
    std::set<std::string> names;
    std::vector<json*> uris;
    for (const char* key : {"buffers", "images"}) {
        const auto list = root.find(key);
        if (list == root.end() || !list->is_array()) continue;
        for (json& entry : *list) {
            const auto uri = entry.find("uri");
            if (uri != entry.end() && uri->is_string()) uris.push_back(&*uri);
        }
    }
    if (const auto materials = root.find("materials");
        materials != root.end() && materials->is_array()) {
        for (std::size_t i = 0; i < materials->size(); ++i) {
            json& material = (*materials)[i];
            if (filtered.count(int(i)) != 0 || !material.is_object()) continue;
            const auto extensions = material.find("extensions");
            if (extensions == material.end() || !extensions->is_object()) continue;
            const auto lean = extensions->find(kGltfLeanMapExtension);
            if (lean == extensions->end() || !lean->is_object()) continue;
            const auto uri = lean->find("uri");
            if (uri != lean->end() && uri->is_string()) uris.push_back(&*uri);
        }
    }
    for (json* uri : uris) {
        const std::string text = uri->get<std::string>();
        if (text.rfind("data:", 0) == 0) continue;
        const std::string source = (input_folder / gltf_uri_path(text)).lexically_normal().string();
        auto found = copied.find(source);
        if (found == copied.end()) {
            if (!resolves_inside(source, input_folder.string()))
                throw Error(input, "'" + escape_text(text, 80) +
                                       "' resolves outside the glTF's folder (through a "
                                       "symbolic link); it cannot be copied beside the output");
            std::error_code error;
            const fs::path resolved = fs::weakly_canonical(source, error);
            if (error)
                throw Error(source, "cannot be resolved (" + error.message() + ")");
            const std::string base = stem + "." + file_name_part(fs::path(source).stem().string());
            const std::string extension = file_name_part(fs::path(source).extension().string().substr(
                std::min<std::size_t>(1, fs::path(source).extension().string().size())));
            const std::string name = unique_name(base, "." + extension, names);
            copies.push_back({source, resolved.string(), name});
            found = copied.emplace(source, name).first;
        }
        *uri = uri_of(found->second);
    }
    return copies;
}

// The files of one material's filtered textures.
struct MaterialFiles {
    int material = -1;  // index into GltfScene::materials
    std::string part;   // its name's file-name part, unique
    std::string lean, roughness, roughness_png, normal, normal_png, anisotropy, anisotropy_png;
    std::string cache_key;  // of its textures and factors (output_cache_key)
    // The earlier job with the same key, whose files this material shares (-1: its own files).
    int same_as = -1;
};

std::string json_text(const json& root) {
    return root.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

// The GLB container of `root` and `bin` (chunks padded to 4 bytes: the JSON with spaces, the
// binary chunk with zeros; glTF 2.0 §4.4).
std::string glb_bytes(const json& root, const std::string* bin) {
    std::string text = root.dump(-1, ' ', false, json::error_handler_t::replace);
    while (text.size() % 4 != 0) text += ' ';
    std::string body;
    append_u32(body, std::uint32_t(text.size()));
    append_u32(body, kGlbChunkJson);
    body += text;
    if (bin != nullptr) {
        std::string padded = *bin;
        while (padded.size() % 4 != 0) padded += '\0';
        append_u32(body, std::uint32_t(padded.size()));
        append_u32(body, kGlbChunkBin);
        body += padded;
    }
    std::string out;
    append_u32(out, kGlbMagic);
    append_u32(out, 2);
    append_u32(out, std::uint32_t(12 + body.size()));
    return out + body;
}

// A file this run wrote into a private folder, read back whole; `failure` is thrown when it
// cannot be (it names what the user knows, not the private path).
std::vector<std::uint8_t> read_file_bytes(const std::string& path, const Error& failure) {
    std::ifstream in(path, std::ios::binary);
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                    std::istreambuf_iterator<char>());
    if (!in) throw failure;  // not opened (istreambuf_iterator sets no state of its own)
    return bytes;
}

// A .glb output holds the files this run writes (LEAN maps, KTX2 and PNG textures) in its binary
// chunk (glTF 2.0 §4.4: buffer 0 without a uri): each image or LEANFADE_lean_map whose uri is a
// key of `files` (uri -> the file written) becomes a buffer view of `bin`, 4-byte aligned; an
// input whose buffer 0 names a file gets a new buffer 0 (the others and their views renumbered).
void embed_in_binary_chunk(json& root, std::string& bin, bool has_bin,
                           const std::map<std::string, std::string>& files,
                           const std::string& output) {
    json& buffers = root["buffers"];
    if (!buffers.is_array()) buffers = json::array();
    if (!has_bin) {
        buffers.insert(buffers.begin(), json{{"byteLength", 0}});
        if (const auto views = root.find("bufferViews"); views != root.end() && views->is_array())
            for (json& view : *views)
                if (view.is_object() && view.contains("buffer") && view["buffer"].is_number_integer())
                    view["buffer"] = view["buffer"].get<int>() + 1;
    }
    json& views = root["bufferViews"];
    if (!views.is_array()) views = json::array();
    const auto embed = [&](const std::string& uri) -> int {
        const std::vector<std::uint8_t> bytes = read_file_bytes(
            files.at(uri), Error(output, "cannot read back " + uri + " to embed it"));
        while (bin.size() % 4 != 0) bin += '\0';
        if (bin.size() + bytes.size() > kMaxGlbBinBytes)
            throw Error(output, "a GLB's binary chunk is at most " + std::to_string(kMaxGlbBinBytes) +
                                    " bytes: write .gltf");
        views.push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}});
        bin.append(bytes.begin(), bytes.end());
        return int(views.size()) - 1;
    };
    if (const auto images = root.find("images"); images != root.end() && images->is_array())
        for (json& image : *images) {
            const auto uri = image.find("uri");
            if (uri == image.end() || !uri->is_string() || !files.count(uri->get<std::string>()))
                continue;
            const std::string name = uri->get<std::string>();
            image["bufferView"] = embed(name);
            if (!image.contains("mimeType"))
                image["mimeType"] = name.ends_with(".png") ? "image/png" : "image/ktx2";
            image.erase("uri");
        }
    if (const auto materials = root.find("materials"); materials != root.end() && materials->is_array())
        for (json& material : *materials) {
            if (!material.is_object() || !material.contains("extensions")) continue;
            json& extensions = material["extensions"];
            if (!extensions.is_object() || !extensions.contains(kGltfLeanMapExtension)) continue;
            json& lean = extensions[kGltfLeanMapExtension];
            const auto uri = lean.find("uri");
            if (uri == lean.end() || !uri->is_string() || !files.count(uri->get<std::string>()))
                continue;
            lean = json{{"bufferView", embed(uri->get<std::string>())}};
        }
    buffers[0]["byteLength"] = bin.size();
}

void add_extension_used(json& root, const std::string& name) {
    json& used = root["extensionsUsed"];
    if (!used.is_array()) used = json::array();
    if (std::find(used.begin(), used.end(), name) == used.end()) used.push_back(name);
}

// A texture of the PNG level 0 `png` with the KTX2 `ktx2` (every level) under
// KHR_texture_basisu; returns its index.
// The texture of a filtered file: added once (with its PNG fallback and the KTX2 under
// KHR_texture_basisu), then shared by every material that uses the same file.
int add_texture(json& root, const std::string& png, const std::string& ktx2, int sampler,
                std::map<std::string, int>& added) {
    if (const auto it = added.find(ktx2); it != added.end()) return it->second;
    json& images = root["images"];
    if (!images.is_array()) images = json::array();
    images.push_back({{"uri", png}, {"mimeType", "image/png"}});
    const int png_index = int(images.size()) - 1;
    images.push_back({{"uri", ktx2}, {"mimeType", "image/ktx2"}});
    const int ktx2_index = int(images.size()) - 1;
    json& textures = root["textures"];
    if (!textures.is_array()) textures = json::array();
    textures.push_back({{"sampler", sampler},
                        {"source", png_index},
                        {"extensions", {{"KHR_texture_basisu", {{"source", ktx2_index}}}}}});
    added.emplace(ktx2, int(textures.size()) - 1);
    return int(textures.size()) - 1;
}

// A textureInfo of `texture` with the normal texture's texCoord and extensions (its
// KHR_texture_transform: the filtered textures share the normal texture's mapping).
json texture_info(int texture, const json& normal_info) {
    json info{{"index", texture}};
    if (normal_info.contains("texCoord")) info["texCoord"] = normal_info["texCoord"];
    if (normal_info.contains("extensions")) info["extensions"] = normal_info["extensions"];
    return info;
}

// The files of one material's engine textures, in a fixed order: roughness KTX2, PNG, normal
// KTX2, PNG, and, when anisotropic, the anisotropy KTX2 and PNG.
struct EngineTextures {
    std::vector<std::vector<std::uint8_t>> files;
    int metallic_roughness_width = 0, metallic_roughness_height = 0;  // its image's; 0: none
    bool anisotropic = false;
    float anisotropy_ratio = 1.0f;  // the whole map's covariance, larger axis over smaller
};

// What a cached material's outputs are: the sizes and SHA-256 of its files (in
// kOutputFileSuffixes order: the LEAN map, then EngineTextures::files), what the summary reports
// and the sizes of the textures it was made from (the run's --max-size applies to them on a
// cache hit as on a bake).
struct CachedOutputs {
    std::vector<std::uint64_t> bytes;
    std::vector<std::string> sha256;
    int metallic_roughness_width = 0, metallic_roughness_height = 0;  // 0: none
    bool anisotropic = false;
    float anisotropy_ratio = 1.0f;
    int levels = 0, width = 0, height = 0;
    bool looks_flipped = false;  // the normal texture looks like a DirectX (-Y) one
};

constexpr const char* kOutputFileSuffixes[] = {".lean.ktx2",      ".roughness.ktx2",
                                               ".roughness.png",  ".normal.ktx2",
                                               ".normal.png",     ".anisotropy.ktx2",
                                               ".anisotropy.png"};
constexpr std::size_t kOutputFileCount = std::size(kOutputFileSuffixes);
constexpr const char* kOutputManifestSuffix = ".gltf-out.json";
// A manifest is a few hundred bytes: one larger is not read (nor parsed) at all.
constexpr std::uint64_t kMaxOutputManifestBytes = 4096;

// The cache key of a material's outputs: its normal texture's and metallic-roughness texture's
// bytes, the normal scale, the roughness factor, the bake settings that change bytes (storage,
// strict normals, supercompression) and the versions of leanfade and of its bake (lean_cache_key).
std::string output_cache_key(const GltfScene& gltf, const GltfMaterial& m,
                             const GltfBakeSettings& settings,
                             const io::WriteOptions& write_options,
                             io::BlockCompression compression) {
    static const std::vector<std::uint8_t> none;
    const std::span<const std::uint8_t> sources[] = {
        gltf.images[std::size_t(m.normal_image)].bytes,
        m.metallic_roughness_image >= 0 ? gltf.images[std::size_t(m.metallic_roughness_image)].bytes
                                        : none};
    std::uint32_t scale = 0, roughness = 0;
    std::memcpy(&scale, &m.normal_scale, 4);
    std::memcpy(&roughness, &m.roughness_factor, 4);
    return lean_cache_key(
        sources, "gltf out v4 scale=" + std::to_string(scale) + " roughness=" +
                    std::to_string(roughness) + " storage=" + to_string(settings.storage) +
                    " strict=" + std::to_string(int(settings.strict_normals)) +
                    " supercompression=" + io::to_string(write_options.supercompression) +
                    (write_options.supercompression == io::Supercompression::Zstandard
                         ? ":" + std::to_string(write_options.zstd_level)
                         : std::string()) +
                    " compress=" + io::to_string(compression));
}

std::optional<CachedOutputs> find_cached_outputs(const LeanMapCache& cache,
                                                 const std::string& key) {
    const auto manifest = cache.find_file(key, kOutputManifestSuffix, kMaxOutputManifestBytes);
    if (!manifest) return std::nullopt;
    CachedOutputs c;
    try {
        const json j = json::parse(manifest->begin(), manifest->end());
        // The entry of this key (not another key's files renamed), with a hash of each file.
        if (j.at("key").get<std::string>() != key) return std::nullopt;
        c.bytes = j.at("bytes").get<std::vector<std::uint64_t>>();
        c.sha256 = j.at("sha256").get<std::vector<std::string>>();
        c.metallic_roughness_width = j.at("metallic_roughness_width").get<int>();
        c.metallic_roughness_height = j.at("metallic_roughness_height").get<int>();
        c.anisotropic = j.at("anisotropic").get<bool>();
        c.anisotropy_ratio = j.at("anisotropy_ratio").get<float>();
        c.levels = j.at("levels").get<int>();
        c.width = j.at("width").get<int>();
        c.height = j.at("height").get<int>();
        c.looks_flipped = j.at("looks_flipped").get<bool>();
    } catch (const json::exception&) {
        return std::nullopt;
    }
    if (c.bytes.size() != (c.anisotropic ? kOutputFileCount : kOutputFileCount - 2)) return std::nullopt;
    if (c.sha256.size() != c.bytes.size()) return std::nullopt;
    return c;
}

// Every file first, the manifest last: an entry without its manifest is not found. `lean_file`:
// the LEAN map as written (copied into the cache, not read back).
std::string store_outputs(const LeanMapCache& cache, const std::string& key,
                          const std::string& lean_file, const EngineTextures& t,
                          const CachedOutputs& outputs) {
    std::string warning = cache.store_file_copy(key, kOutputFileSuffixes[0], lean_file, outputs.bytes[0]);
    if (!warning.empty()) return warning;
    for (std::size_t i = 0; i < t.files.size(); ++i) {
        warning = cache.store_file(key, kOutputFileSuffixes[i + 1], t.files[i]);
        if (!warning.empty()) return warning;
    }
    const std::string manifest = json{{"key", key},
                                      {"bytes", outputs.bytes},
                                      {"sha256", outputs.sha256},
                                      {"metallic_roughness_width", outputs.metallic_roughness_width},
                                      {"metallic_roughness_height", outputs.metallic_roughness_height},
                                      {"anisotropic", outputs.anisotropic},
                                      {"anisotropy_ratio", outputs.anisotropy_ratio},
                                      {"levels", outputs.levels},
                                      {"width", outputs.width},
                                      {"height", outputs.height},
                                      {"looks_flipped", outputs.looks_flipped}}
                                     .dump();
    return cache.store_file(key, kOutputManifestSuffix,
                            std::vector<std::uint8_t>(manifest.begin(), manifest.end()));
}

// A material's engine textures from its LEAN map (the map as stored) and its own roughness.
EngineTextures make_engine_textures(const GltfScene& gltf, const GltfMaterial& m,
                                    const PackedLeanMap& packed, const io::ReadOptions& read_options,
                                    int threads, const std::string& writer,
                                    const std::string& input, io::BlockCompression compression) {
    const LeanMap lean = unpack_lean_map(packed);
    const int w = lean.levels.front().width, h = lean.levels.front().height;
    // The material's own roughness, r = roughnessFactor x G of its texture; its R, B
    // (occlusion, metallic) kept. Without a texture, B = 1 keeps metallicFactor as it was.
    Image metallic_roughness(w, h, 3, 1.0f);
    std::pair<int, int> decoded_size{0, 0};
    if (m.metallic_roughness_image >= 0) {
        const GltfImage& image = gltf.images[std::size_t(m.metallic_roughness_image)];
        Image decoded = io::read_image_from_memory(image.bytes, image.name, read_options);
        decoded_size = {decoded.width, decoded.height};
        if (decoded.channels < 3)
            throw Error(input, image.name + ": a metallic-roughness texture has 3 or 4 channels");
        metallic_roughness = resampled(decoded, w, h);
    }
    Image base = base_roughness_channel(metallic_roughness);
    for (float& r : base.pixels) r *= m.roughness_factor;
    RoughnessOptions ro;
    ro.base_roughness = m.roughness_factor;
    ro.threads = threads;
    if (m.metallic_roughness_image >= 0) ro.roughness_map = &base;
    // The whole map's covariance: its axes' variances (eigenvalues) and their ratio; a map
    // without slope variance (flat, or one constant tilt) is not anisotropic.
    const glm::vec3 c = summarize(lean).coarsest_covariance;  // xx, yy, xy
    const float mean = 0.5f * (c.x + c.y);
    const float half_gap = std::sqrt(0.25f * (c.x - c.y) * (c.x - c.y) + c.z * c.z);
    const float larger = mean + half_gap, smaller = std::max(mean - half_gap, 0.0f);
    EngineTextures t;
    t.metallic_roughness_width = decoded_size.first;
    t.metallic_roughness_height = decoded_size.second;
    t.anisotropy_ratio = larger > 1e-8f ? larger / std::max(smaller, 1e-12f) : 1.0f;
    t.anisotropic = larger > 1e-8f && t.anisotropy_ratio >= kAnisotropyThreshold;
    const RoughnessTexturesRgba8 textures =
        roughness_textures_rgba8(lean, ro, &metallic_roughness, {true, t.anisotropic});
    std::vector<const std::vector<Rgba8Image>*> chains{&textures.metallic_roughness,
                                                       &textures.normal};
    std::vector<const char*> contents{"roughness", "normal"};
    if (t.anisotropic) {
        chains.push_back(&textures.anisotropy);
        contents.push_back("anisotropy");
    }
    // Basis Universal UASTC (KHR_texture_basisu's payload): every chain in one run of the
    // encoder, through a private folder.
    std::vector<std::vector<std::uint8_t>> basis_files;
    if (compression == io::BlockCompression::Basis) {
        if (w % 4 != 0 || h % 4 != 0)
            throw Error(gltf.images[std::size_t(m.normal_image)].name,
                        "is " + std::to_string(w) + " x " + std::to_string(h) +
                            ": KHR_texture_basisu images have sides that are multiples of 4 "
                            "(use --compress none)");
        const io::ScratchFolder scratch("leanfade-gltf-basis");
        std::vector<io::UastcTexture> uastc;
        for (std::size_t i = 0; i < chains.size(); ++i)
            uastc.push_back({(scratch.path() / (std::string(contents[i]) + ".ktx2")).string(),
                             chains[i], false});
        io::write_ktx2_uastc(uastc, writer, io::find_node_script(io::kUastcEncoderScript));
        for (const io::UastcTexture& u : uastc)
            basis_files.push_back(read_file_bytes(
                u.output, Error(input, "cannot read back the encoded " +
                                           fs::path(u.output).stem().string() + " texture")));
    }
    for (std::size_t i = 0; i < chains.size(); ++i) {
        const std::vector<Rgba8Image>& levels = *chains[i];
        t.files.push_back(basis_files.empty()
                              ? io::encode_ktx2_rgba8(levels, writer, contents[i],
                                                      {{io::kKeyTextureContent,
                                                        std::string(contents[i]) + " v1"}})
                              : std::move(basis_files[i]));
        t.files.push_back(io::encode_png_rgba8(levels.front(), contents[i]));
    }
    return t;
}

}  // namespace

std::string file_name_part(const std::string& name) {
    std::string out;
    for (char c : name.substr(0, 64))
        out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
    return out.empty() ? "material" : out;
}

std::string unique_name(const std::string& base, const std::string& suffix,
                        std::set<std::string>& taken) {
    std::string name = base + suffix;
    for (int n = 2; taken.count(name) != 0; ++n) name = base + "-" + std::to_string(n) + suffix;
    taken.insert(name);
    return name;
}

void write_filtered_gltf(const std::string& input, const std::string& output,
                         const FilteredGltfSettings& settings_in, FilteredGltfReport* report,
                         const GltfWriteProgress& progress) {
    FilteredGltfReport local_report;
    FilteredGltfReport& found = report != nullptr ? *report : local_report;
    const std::string extension = fs::path(output).extension().string();
    if (extension != ".gltf" && extension != ".glb")
        throw Error(output, "a glTF output is a .gltf or .glb file");
    if (settings_in.compression != io::BlockCompression::None &&
        settings_in.compression != io::BlockCompression::Basis)
        throw Error::setting("compress",
                             "a glTF's KHR_texture_basisu images are basis (Basis Universal "
                             "UASTC) or none (RGBA8 KTX2)");
    const bool binary_out = extension == ".glb";

    const GltfScene gltf = load_gltf(input);
    found.warnings.insert(found.warnings.end(), gltf.warnings.begin(), gltf.warnings.end());
    Container container = read_container(input);
    json& root = container.root;

    const fs::path out_path = fs::absolute(output).lexically_normal();
    const fs::path out_folder = out_path.parent_path();
    const fs::path in_folder = fs::absolute(input).lexically_normal().parent_path();
    const std::string stem = out_path.stem().string();
    // Files beside the output, named as the output is (relative when it is).
    const auto beside = [&](const std::string& name) {
        return (fs::path(output).parent_path() / name).string();
    };

    // The materials to filter: those with a normal texture, each file name once.
    std::vector<MaterialFiles> jobs;
    std::set<std::string> parts;
    for (std::size_t i = 0; i < gltf.materials.size(); ++i) {
        const GltfMaterial& m = gltf.materials[i];
        if (m.normal_image < 0 || m.gltf_index < 0) continue;
        const std::string part = unique_name(file_name_part(m.name), "", parts);
        MaterialFiles f;
        f.material = int(i);
        f.part = part;
        const std::string prefix = stem + "." + part;
        f.lean = prefix + ".lean.ktx2";
        f.roughness = prefix + ".roughness.ktx2";
        f.roughness_png = prefix + ".roughness.png";
        f.normal = prefix + ".normal.ktx2";
        f.normal_png = prefix + ".normal.png";
        f.anisotropy = prefix + ".anisotropy.ktx2";
        f.anisotropy_png = prefix + ".anisotropy.png";
        jobs.push_back(f);
    }
    if (jobs.empty()) throw Error(input, "no material of the scene has a normal texture");
    const GltfBakeSettings& settings = settings_in.bake;
    const io::Durability durability = settings_in.durability;
    io::WriteOptions write_options;
    write_options.durability = durability;
    write_options.supercompression = settings_in.supercompression;
    write_options.zstd_level = settings_in.zstd_level;
    // Materials with the same normal texture, metallic-roughness texture and factors get the same
    // files: written once, under the first one's names.
    {
        std::map<std::string, int> first_of;
        for (std::size_t j = 0; j < jobs.size(); ++j) {
            MaterialFiles& f = jobs[j];
            f.cache_key = output_cache_key(gltf, gltf.materials[std::size_t(f.material)], settings,
                                           write_options, settings_in.compression);
            const auto [it, added] = first_of.emplace(f.cache_key, int(j));
            if (added) continue;
            // The first material's file names; its own index, name part and key.
            MaterialFiles shared = jobs[std::size_t(it->second)];
            shared.material = f.material;
            shared.part = f.part;
            shared.cache_key = f.cache_key;
            shared.same_as = it->second;
            f = std::move(shared);
        }
    }
    // A .gltf out of a .glb: its binary chunk becomes a file beside the output.
    const bool writes_bin = !binary_out && container.has_bin;
    const std::string bin_name = stem + ".bin";

    std::set<int> filtered;
    for (const MaterialFiles& f : jobs) filtered.insert(gltf.materials[std::size_t(f.material)].gltf_index);
    const std::vector<CopiedFile> copies =
        relocate_external_files(root, input, in_folder, out_folder, stem, filtered);
    io::OutputPlan plan;
    plan.add_input(input);
    for (const CopiedFile& c : copies) plan.add_output(beside(c.target), "a copy of " + c.source);
    for (const std::string& file : gltf_referenced_files(input)) plan.add_input(file);
    plan.add_output(output, "the glTF output");
    if (writes_bin) plan.add_output(beside(bin_name), "the glTF output (its binary chunk)");
    // A .glb holds the files this run writes in its binary chunk (embed_in_binary_chunk): they
    // are written into a private folder first, never beside it.
    const bool embeds = binary_out;
    for (const MaterialFiles& f : jobs) {
        if (f.same_as >= 0 || embeds) continue;  // the files of an earlier material, or embedded
        for (const std::string* file : {&f.lean, &f.roughness, &f.roughness_png, &f.normal,
                                        &f.normal_png, &f.anisotropy, &f.anisotropy_png})
            plan.add_output(beside(*file), "material '" + gltf.materials[std::size_t(f.material)].name + "'");
    }
    if (!settings_in.summary_path.empty()) plan.add_output(settings_in.summary_path, "the summary");
    plan.check();

    io::ReadOptions read_options;
    read_options.max_dimension = settings.max_image_size;

    io::OutputTransaction outputs(durability);
    const std::string writer = std::string(LEANFADE_GENERATOR);
    std::vector<std::string>& written = found.written;
    written.clear();
    nlohmann::json summaries = nlohmann::json::array();
    const LeanMapCache cache(settings.cache_folder);
    std::map<std::string, std::string> staged_paths;  // an output's file name -> its temporary
    const io::ScratchFolder embedded("leanfade-glb");  // a .glb's files before they are embedded

    // One trilinear, repeating sampler for the filtered textures (every level is used).
    json& samplers = root["samplers"];
    if (!samplers.is_array()) samplers = json::array();
    samplers.push_back({{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}});
    const int sampler = int(samplers.size()) - 1;
    if (writes_bin) root["buffers"][0]["uri"] = uri_of(bin_name);
    std::map<std::string, int> textures_added;  // KTX2 file -> its texture (add_texture)
    std::vector<std::optional<CachedOutputs>> results(jobs.size());

    try {
        for (std::size_t j = 0; j < jobs.size(); ++j) {
            const MaterialFiles& f = jobs[j];
            const GltfMaterial& m = gltf.materials[std::size_t(f.material)];
            if (progress) progress(j, jobs.size(), m.name);
            const auto start = std::chrono::steady_clock::now();
            const std::string* const names[kOutputFileCount] = {
                &f.lean,   &f.roughness,  &f.roughness_png, &f.normal,
                &f.normal_png, &f.anisotropy, &f.anisotropy_png};
            const auto staged = [&](std::size_t file) -> const std::string& {
                auto it = staged_paths.find(*names[file]);
                if (it == staged_paths.end())
                    it = staged_paths
                             .emplace(*names[file],
                                      embeds ? (embedded.path() / fs::path(*names[file]).filename()).string()
                                             : outputs.stage(beside(*names[file])))
                             .first;
                return it->second;
            };
            // The files of an earlier run for the same textures and factors, copied from the
            // cache (in the kernel, without reading them); anything missing or of another size
            // and the material is filtered again.
            const std::string& cache_key = f.cache_key;
            std::optional<CachedOutputs>& result = results[j];
            if (f.same_as >= 0) result = results[std::size_t(f.same_as)];
            else result = find_cached_outputs(cache, cache_key);
            if (result && f.same_as < 0) {
                // The limits a bake applies to the textures' headers, on the sizes the entry
                // records: a warm cache refuses what an empty one does.
                check_cached_image_size(gltf, m.normal_image, result->width, result->height,
                                               read_options.max_dimension);
                if (m.metallic_roughness_image >= 0 &&
                    (result->metallic_roughness_width > read_options.max_dimension ||
                     result->metallic_roughness_height > read_options.max_dimension))
                    throw Error(gltf.images[std::size_t(m.metallic_roughness_image)].name,
                                "image size " + std::to_string(result->metallic_roughness_width) +
                                    "x" + std::to_string(result->metallic_roughness_height) +
                                    " exceeds the limit of " +
                                    std::to_string(read_options.max_dimension) +
                                    " texels per side");
                // Each copy is what the manifest hashed, or the material is filtered again: an
                // entry of the right size with other bytes (corrupt, another key's file renamed)
                // is never published.
                try {
                    for (std::size_t i = 0; result && i < result->bytes.size(); ++i) {
                        io::AtomicFile file(staged(i), durability);
                        if (!cache.copy_file_to(cache_key, kOutputFileSuffixes[i], result->bytes[i], file)) {
                            result.reset();
                        } else {
                            file.commit();
                            if (sha256_file_hex(staged(i)) != result->sha256[i]) result.reset();
                        }
                    }
                } catch (const Error&) {
                    result.reset();
                }
            }
            // Not made by this run's bake: copied from the cache, or the files of an earlier
            // material (same_files_as).
            const bool from_cache = result.has_value();
            if (!result) {
                const PackedLeanMap packed =
                    bake_normal_texture(gltf, m.normal_image, m.normal_scale, settings);
                io::write_ktx2(staged(0), packed, write_options);
                const EngineTextures textures =
                    make_engine_textures(gltf, m, packed, read_options, settings.threads, writer,
                                         input, settings_in.compression);
                result.emplace();
                result->bytes.push_back(fs::file_size(staged(0)));
                result->sha256.push_back(sha256_file_hex(staged(0)));
                for (std::size_t i = 0; i < textures.files.size(); ++i) {
                    io::AtomicFile file(staged(i + 1), durability);
                    file.write(textures.files[i]);
                    file.commit();
                    result->bytes.push_back(textures.files[i].size());
                    result->sha256.push_back(
                        sha256_hex(textures.files[i].data(), textures.files[i].size()));
                }
                result->metallic_roughness_width = textures.metallic_roughness_width;
                result->metallic_roughness_height = textures.metallic_roughness_height;
                result->anisotropic = textures.anisotropic;
                result->anisotropy_ratio = textures.anisotropy_ratio;
                result->levels = int(packed.levels.size());
                result->width = packed.levels.front().width;
                result->height = packed.levels.front().height;
                result->looks_flipped = packed.source_looks_flipped;
                const std::string warning = store_outputs(cache, cache_key, staged(0), textures, *result);
                // Named as the outputs, never as their temporaries.
                if (!warning.empty())
                    found.warnings.push_back("cache: " +
                                             std::string(outputs.named(Error("", warning)).cause()));
            }
            if (f.same_as < 0 && !embeds)
                for (std::size_t i = 0; i < result->bytes.size(); ++i)
                    written.push_back(beside(*names[i]));
            // The convention warning of every bake path, from the cache too.
            if (result->looks_flipped && f.same_as < 0)
                found.other_convention.push_back(gltf.images[std::size_t(m.normal_image)].name);
            const bool anisotropic = result->anisotropic;
            const float anisotropy = result->anisotropy_ratio;

            // The material, pointed at the filtered textures.
            json& material = root["materials"][std::size_t(m.gltf_index)];
            const json normal_info = material["normalTexture"];
            json& pbr = material["pbrMetallicRoughness"];
            if (!pbr.is_object()) pbr = json::object();
            pbr["metallicRoughnessTexture"] =
                texture_info(add_texture(root, uri_of(f.roughness_png), uri_of(f.roughness), sampler,
                                         textures_added),
                             normal_info);
            pbr["roughnessFactor"] = 1.0;  // G holds the whole roughness now
            json normal = texture_info(
                add_texture(root, uri_of(f.normal_png), uri_of(f.normal), sampler, textures_added),
            normal_info);
            material["normalTexture"] = normal;  // scale 1: the normals hold the scaled slopes
            json& extensions = material["extensions"];
            if (!extensions.is_object()) extensions = json::object();
            if (anisotropic && !extensions.contains("KHR_materials_anisotropy")) {
                extensions["KHR_materials_anisotropy"] = {
                    {"anisotropyStrength", 1.0},
                    {"anisotropyTexture",
                     texture_info(add_texture(root, uri_of(f.anisotropy_png), uri_of(f.anisotropy),
                                              sampler, textures_added),
                                  normal_info)}};
                add_extension_used(root, "KHR_materials_anisotropy");
            }
            extensions[kGltfLeanMapExtension] = {{"uri", uri_of(f.lean)}};
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            summaries.push_back({{"input", input},
                                 {"material", m.name},
                                 {"lean_map", beside(f.lean)},
                                 {"roughness", beside(f.roughness)},
                                 {"normal", beside(f.normal)},
                                 {"anisotropy", anisotropic ? json(beside(f.anisotropy)) : json()},
                                 {"anisotropy_ratio", anisotropy},
                                 {"textures_from_cache", from_cache},
                                 // In a .glb: the files are buffer views of its binary chunk,
                                 // named here as they would be beside it.
                                 {"embedded", embeds},
                                 {"same_files_as",
                                  f.same_as >= 0
                                      ? json(gltf.materials[std::size_t(jobs[std::size_t(f.same_as)].material)].name)
                                      : json()},
                                 {"levels", result->levels},
                                 {"width", result->width},
                                 {"height", result->height},
                                 {"seconds", seconds}});
        }
        add_extension_used(root, "KHR_texture_basisu");
        add_extension_used(root, kGltfLeanMapExtension);

        if (embeds) {
            std::map<std::string, std::string> files;  // uri -> the file written
            for (const auto& [name, path] : staged_paths) files.emplace(uri_of(name), path);
            embed_in_binary_chunk(root, container.bin, container.has_bin, files, output);
            container.has_bin = true;
        }
        const std::string bytes =
            binary_out ? glb_bytes(root, container.has_bin ? &container.bin : nullptr)
                       : json_text(root);
        {
            io::AtomicFile file(outputs.stage(output), durability);
            file.write(bytes.data(), bytes.size());
            file.commit();
        }
        written.insert(written.begin(), output);
        if (writes_bin) {
            io::AtomicFile file(outputs.stage(beside(bin_name)), durability);
            file.write(container.bin.data(), container.bin.size());
            file.commit();
            written.insert(written.begin() + 1, beside(bin_name));
        }
        for (const CopiedFile& c : copies) {
            // Copied in the kernel (shared blocks where the file system has them).
            std::error_code error;
            const std::uintmax_t size = fs::file_size(c.resolved, error);
            if (error) throw Error(c.source, "cannot read its size (" + error.message() + ")");
            if (size > kMaxGltfFileBytes)
                throw Error(c.source, "a glTF file is at most " + std::to_string(kMaxGltfFileBytes) +
                                          " bytes, it has " + std::to_string(size));
            io::AtomicFile file(outputs.stage(beside(c.target)), durability);
            file.copy_from(c.resolved, size);
            file.commit();
            written.push_back(beside(c.target));
        }
        if (!settings_in.summary_path.empty()) {
            const std::string text = json_text(summaries);
            io::AtomicFile file(outputs.stage(settings_in.summary_path), durability);
            file.write(text.data(), text.size());
            file.commit();
            written.push_back(settings_in.summary_path);
        }
    } catch (const Error& e) {
        throw outputs.named(e);
    }
    outputs.publish();
    found.materials = jobs.size();
}

}  // namespace leanfade::scene
