#pragma once
// Plain 2D textures with their MIP chain as KTX 2.0 files (Khronos,
// https://registry.khronos.org/KTX/specs/2.0/ktxspec.v2.html), in the form common loaders read:
// one layer, one face, no supercompression, linear transfer (the textures are data: roughness,
// normals, anisotropy, the plateau layer of two-lobe LEAN; docs/roughness.md, docs/ktx2.md).
// Two formats: VK_FORMAT_R8G8B8A8_UNORM (`leanfade bake --roughness-out`, --anisotropy-out) and
// VK_FORMAT_R16G16B16A16_SFLOAT (`--plateau-out`; WebGL2 filters half floats without
// extensions). LEAN maps have their own container (ktx2.hpp).
//
// Rows are top row first (KTXorientation "rd"); level 0 (the largest) first in the level index,
// level data from the smallest to the largest in the file, each level aligned to lcm(texel size,
// 4). Key/value data: KTXorientation, KTXwriter and the caller's keys (LEANFADEcontent, ...),
// sorted by key. Every failure throws leanfade::Error(file, cause); files are written atomically
// (AtomicFile).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::io {

// One MIP level of 8-bit RGBA texels, rows top first: width * height * 4 bytes.
using Rgba8Level = ::leanfade::Rgba8Image;

// Key/value pairs a texture carries besides KTXorientation and KTXwriter (keys not starting with
// "KTX", each once; written sorted by key).
using TextureKeyValues = std::vector<std::pair<std::string, std::string>>;

// The key naming what a leanfade texture holds (docs/ktx2.md): "roughness", "normal",
// "anisotropy", "plateau", each followed by " v1".
inline constexpr const char* kKeyTextureContent = "LEANFADEcontent";

// The bytes of a KTX2 file of `levels` (level 0 first; sizes halving with floor down to 1 x 1,
// the full chain), KTXwriter = `writer`. Throws leanfade::Error(name, cause) for an empty or
// broken chain, wrong byte counts or a reserved or repeated key.
std::vector<std::uint8_t> encode_ktx2_rgba8(const std::vector<Rgba8Level>& levels,
                                            const std::string& writer,
                                            const std::string& name = "texture",
                                            const TextureKeyValues& key_values = {});

// encode_ktx2_rgba8 written atomically to `path`.
void write_ktx2_rgba8(const std::string& path, const std::vector<Rgba8Level>& levels,
                      const std::string& writer, const WriteOptions& options = {},
                      const TextureKeyValues& key_values = {});

// The same file written in place: sized (disk space reserved) and mapped when constructed, with
// the head written; the caller fills every level's texels (level 0 first, width * height * 4
// bytes, rows top first; from several threads if it likes; e.g. a RoughnessTextureBuilder's
// targets), then commit() publishes it atomically. Nothing appears at `path` without commit().
// The same bytes as write_ktx2_rgba8 of those levels. Throws leanfade::Error(path, cause).
class Ktx2Rgba8Writer {
  public:
    Ktx2Rgba8Writer(const std::string& path, int width, int height, const std::string& writer,
                    const TextureKeyValues& key_values = {}, const WriteOptions& options = {});
    // Each level's first texel, level 0 first (the full chain down to 1 x 1). Valid until commit().
    const std::vector<std::uint8_t*>& levels() const noexcept { return levels_; }
    void commit();

  private:
    AtomicFile file_;
    std::vector<std::uint8_t*> levels_;
};

// The same for 4-channel float images stored as half floats (VK_FORMAT_R16G16B16A16_SFLOAT, each
// value rounded to the nearest half). Throws also for images that are not 4 channels or hold a
// value that is not finite or beyond the half range (65504).
std::vector<std::uint8_t> encode_ktx2_rgba16f(const std::vector<Image>& levels,
                                              const std::string& writer,
                                              const std::string& name = "texture",
                                              const TextureKeyValues& key_values = {});
void write_ktx2_rgba16f(const std::string& path, const std::vector<Image>& levels,
                        const std::string& writer, const WriteOptions& options = {},
                        const TextureKeyValues& key_values = {});

// A LEAN map's two layers as plain 2D textures (`bake --ktx2-2d`), for loaders that read no array
// layers (three.js's KTX2Loader among them): `lean1_path` holds layer 0 (lean1) and `lean2_path`
// layer 1 (lean2), every level, in the map's own format (R8G8B8A8_UNORM, R16G16B16A16_UNORM,
// _SFLOAT or R32G32B32A32_SFLOAT), the same bytes as the array's layers, with the map's LEANFADE
// keys (sc and the rest, docs/ktx2.md) and LEANFADEcontent "lean1 v1" / "lean2 v1" in place of
// LEANFADElayout. Each file written atomically; throws leanfade::Error(file, cause).
void write_ktx2_layer_textures(const std::string& lean1_path, const std::string& lean2_path,
                               const PackedLeanMap& map, const WriteOptions& options = {});

// Reads the levels of a file in the forms above back (for tests and tools): checks the structure
// with inspect_ktx2 (ktx2.hpp), then that it is a 2D texture of the format with one layer and
// one face, and copies each level. Throws leanfade::Error(path, cause).
std::vector<Rgba8Level> read_ktx2_rgba8(const std::string& path);
std::vector<Image> read_ktx2_rgba16f(const std::string& path);

}  // namespace leanfade::io
