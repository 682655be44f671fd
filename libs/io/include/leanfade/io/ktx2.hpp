#pragma once
// The LEAN map container: a Khronos KTX 2.0 file holding a 2D array texture of two layers
// (layer 0 = lean1, layer 1 = lean2, docs/math.md §3), or three with two-lobe LEAN's plateau layer
// (layer 2, docs/math.md §10), with its MIP chain. See docs/ktx2.md.
//
// - vkFormat from the storage: Unorm8 -> VK_FORMAT_R8G8B8A8_UNORM (37), Unorm16 ->
//   R16G16B16A16_UNORM (91), Float16 -> R16G16B16A16_SFLOAT (97), Float32 -> R32G32B32A32_SFLOAT
//   (109). Values are data (transfer function LINEAR, no sRGB), little-endian.
// - Rows are top row first (KTXorientation "rd"), exactly as in PackedLevel.
// - Level index: level 0 (the largest) first; level data in the file from the smallest level to
//   the largest, each level's layers back to back, each level aligned to lcm(texel size, 4).
// - Key/value data: KTXorientation, KTXwriter and the LEANFADE* keys (scale, roughness baking,
//   normal convention, layout), sorted by key.
// Every failure throws leanfade::Error(file, cause). write_ktx2 writes atomically (AtomicFile).
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::io {

inline constexpr std::uint32_t kVkFormatR8G8B8A8Unorm = 37;
inline constexpr std::uint32_t kVkFormatR16G16B16A16Unorm = 91;
inline constexpr std::uint32_t kVkFormatR16G16B16A16Sfloat = 97;
inline constexpr std::uint32_t kVkFormatR32G32B32A32Sfloat = 109;

// The keys of the LEAN map's metadata (docs/ktx2.md), written alike as KTX2 key/value data and as
// the text chunks of a PNG pair (png_io.hpp).
inline constexpr const char* kLayoutKey = "LEANFADElayout";
inline constexpr const char* kScaleKey = "LEANFADEscale";
inline constexpr const char* kRoughnessBakedKey = "LEANFADEroughnessBaked";
inline constexpr const char* kBakedShininessKey = "LEANFADEbakedShininess";
inline constexpr const char* kNormalConventionKey = "LEANFADEnormalConvention";
// Written only when not 0 (NormalRepairs): the source's (0, 0, 0) padding texels taken as flat
// and its texels with z <= 0 raised.
inline constexpr const char* kPaddingTexelsKey = "LEANFADEpaddingTexels";
inline constexpr const char* kRaisedTexelsKey = "LEANFADEraisedTexels";
// Written only when a bake found its source normal map to fit the other convention better
// (PackedLeanMap::source_looks_flipped): the value "other".
inline constexpr const char* kConventionWarningKey = "LEANFADEconventionWarning";

// The value of the LEANFADElayout key of a LEAN map of two layers (lean1, lean2) ...
inline constexpr const char* kLeanLayoutName = "lean1,lean2 v1";
// ... and of one with two-lobe LEAN's plateau layer as a third (PackedLevel::plateau,
// leanfade/core/detail/plateau.hpp), made with the epsilon of LEANFADEplateauEpsilon. A reader that
// takes only the first two layers reads it as the two-layer map.
inline constexpr const char* kLeanPlateauLayoutName = "lean1,lean2,plateau v1";
// Version 2 of both: the signed encoding of float storages (LeanEncoding::Signed, leanfade 0.2):
// n, B / sc, Mxy / sc^2 stored as they are, without version 1's 0.5 v + 0.5. Version 1 files
// (UNORM, and the float maps of leanfade 0.1) keep the offset encoding and load as before.
inline constexpr const char* kLeanSignedLayoutName = "lean1,lean2 v2";
inline constexpr const char* kLeanSignedPlateauLayoutName = "lean1,lean2,plateau v2";
// The LEANFADElayout value of a LEAN map of this encoding, with or without the plateau layer.
const char* lean_layout_name(LeanEncoding encoding, bool plateau);
// Whether `layout` is one of the four LEANFADElayout values of a LEAN map above.
bool is_lean_layout_name(std::string_view layout);
inline constexpr const char* kPlateauEpsilonKey = "LEANFADEplateauEpsilon";
// The LEANFADElayout of a cross-term texture (`bake --cross-terms`, docs/ktx2.md): the same
// container, other layers; read_ktx2 refuses it by name.
inline constexpr const char* kCrossTermLayoutName = "cross terms v1";

// vkFormat of a storage, and its Vulkan name ("VK_FORMAT_R16G16B16A16_UNORM").
std::uint32_t vk_format_of(Storage storage);
const char* vk_format_name(std::uint32_t vk_format);  // "unknown" for others
// A KTX2 supercompressionScheme's name ("none", "BasisLZ", "Zstandard", "ZLIB"; else "unknown").
const char* supercompression_name(std::uint32_t scheme);

// Writes `map` (the full chain of levels, sizes halving with floor down to 1x1; both layers
// of every level width * height * bytes_per_texel(storage) bytes, rows top first). Throws on an
// inconsistent map (sizes, chain, byte counts, scale not finite and > 0, shininess not finite and
// >= 0). The generator string becomes KTXwriter ("leanfade <version>" when empty).
void write_ktx2(const std::string& path, const PackedLeanMap& map,
                const WriteOptions& options = {});

// write_ktx2 of a cross-term texture: its LEANFADElayout is kCrossTermLayoutName.
void write_cross_term_ktx2(const std::string& path, const PackedLeanMap& map,
                           const WriteOptions& options = {});

// The bytes write_ktx2 writes for `map`, in memory (for an engine's own asset pipeline or
// archive): the same checks, with `name` in their errors. The inverse of read_ktx2_from_memory.
// options.supercompression and zstd_level are honoured (durability and threads: the threads of
// the compression).
std::vector<std::uint8_t> write_ktx2_to_memory(const PackedLeanMap& map,
                                               const std::string& name = "LEAN map",
                                               const WriteOptions& options = {});

// A LEAN map written in place (what write_ktx2 does, without the map in memory): the
// constructor creates the temporary output file with its final size, writes the header, level
// index, DFD and key/value data from `layout` (the map's metadata and level sizes, checked as
// write_ktx2 checks them; its layers may be empty unless check_layers) and maps the file; the
// caller fills each level's layers through targets() (e.g. bake_packed_to, from several threads)
// and calls commit(), which replaces `path` atomically (AtomicFile). Without commit() nothing
// appears. Not copyable, not movable. With options.supercompression Zstandard the levels are
// filled in memory and compressed by commit() (each level one frame), which then writes the file.
class Ktx2Writer {
  public:
    // `layout_name`: the LEANFADElayout value (kLeanLayoutName or kCrossTermLayoutName).
    Ktx2Writer(std::string path, const PackedLeanMap& layout, const WriteOptions& options = {},
               bool check_layers = false, const char* layout_name = kLeanLayoutName);
    ~Ktx2Writer();
    Ktx2Writer(const Ktx2Writer&) = delete;
    Ktx2Writer& operator=(const Ktx2Writer&) = delete;
    // One per level, level 0 first: where lean1 and lean2 go (width * height * texel bytes each,
    // rows top first). Valid until commit().
    const std::vector<PackedLevelTarget>& targets() const noexcept { return targets_; }
    // Before commit(), for a supercompressed file whose layout has the plateau layer: the file
    // is written without it (its layout, key/value data and levels of two layers), as a map
    // without one. Returns false, changing nothing, for an uncompressed file (whose size is
    // fixed) or a layout without the layer.
    bool drop_plateau_layer();
    void commit();

  private:
    struct Staging;
    AtomicFile file_;
    std::vector<PackedLevelTarget> targets_;
    std::unique_ptr<Staging> staging_;  // supercompressed files only
};

// A bake's map (bake(input, settings, sink), leanfade/core/lean_map.hpp) written in place into the
// KTX2 file `path`: a Ktx2Writer opened once sc is known (a second open, the second bake of
// `--bits auto`, discards the first unwritten) and committed by finish(). What `leanfade bake`
// does, with no copy of the map in memory: the same bytes as write_ktx2 of the map bake() makes
// in memory. A plateau layer the bake drops leaves the file too: a supercompressed file is
// written without it; an uncompressed one, whose size was fixed, is written again (read back
// with `read_options`). Nothing appears at `path` unless finish() ran.
class Ktx2FileSink : public BakeSink {
  public:
    explicit Ktx2FileSink(std::string path, const WriteOptions& write_options = {},
                          const ReadOptions& read_options = {});
    ~Ktx2FileSink() override;
    std::vector<PackedLevelTarget> open(const PackedLeanMap& layout, int threads) override;
    void finish(PackedBakeResult& result, bool drop_plateau) override;

  private:
    std::string path_;
    WriteOptions write_options_;
    ReadOptions read_options_;
    std::unique_ptr<Ktx2Writer> writer_;
};

// Reads a LEAN map written by write_ktx2 (bit-exact) or by any writer following the same layout.
// Validates the identifier, the header (one of our four formats and its typeSize, width and
// height in [1, max_dimension], depth 0, layerCount 2, or 3 with the plateau layer, faceCount 1,
// levelCount the full MIP chain, no supercompression or Zstandard, each level one frame of
// exactly its bytes), that every offset + length lies inside
// the file (overflow-safe),
// that no two parts of the file (header and level index, DFD, key/value data, each level)
// overlap, that level data is aligned and exactly sized, the data format descriptor, the key/value
// data (no key twice) and the LEANFADE keys (LEANFADEscale finite and > 0; LEANFADElayout naming
// the plateau layer exactly when there are 3 layers, with LEANFADEplateauEpsilon > 0), and that
// every texel
// of a float map is finite. Sizes are checked before any level memory is allocated. inspect_ktx2
// runs the structural part of these checks; `leanfade info` runs both before printing anything.
PackedLeanMap read_ktx2(const std::string& path, const ReadOptions& options = {});

// read_ktx2 of a cross-term texture (write_cross_term_ktx2): the same checks, the layout
// kCrossTermLayoutName; a LEAN map is refused.
PackedLeanMap read_cross_term_ktx2(const std::string& path, const ReadOptions& options = {});

// read_ktx2 on a file's bytes already in memory (same checks and messages); `name` is the file
// name the errors give.
PackedLeanMap read_ktx2_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& name,
                                    const ReadOptions& options = {});

struct Ktx2Sample {
    std::uint32_t bit_offset = 0;
    std::uint32_t bit_length = 0;    // number of bits (the file stores bit_length - 1)
    std::uint32_t channel_id = 0;    // RGBSDA: 0 R, 1 G, 2 B, 15 A
    std::uint32_t qualifiers = 0;    // 0x8 float, 0x4 signed, 0x2 exponent, 0x1 linear
    std::uint32_t sample_lower = 0;  // raw 32-bit values (IEEE bits for float formats)
    std::uint32_t sample_upper = 0;
};

// The Basic Data Format Descriptor block (the only one leanfade writes or reads).
struct Ktx2DataFormat {
    std::uint32_t total_size = 0;  // dfdTotalSize
    std::uint32_t vendor_id = 0;
    std::uint32_t descriptor_type = 0;
    std::uint32_t version_number = 0;
    std::uint32_t descriptor_block_size = 0;
    std::uint32_t color_model = 0;                           // 1 = RGBSDA
    std::uint32_t color_primaries = 0;                       // 1 = BT709
    std::uint32_t transfer_function = 0;                     // 1 = LINEAR, 2 = sRGB
    std::uint32_t flags = 0;                                 // 1 = premultiplied alpha
    std::uint32_t texel_block_dimensions[4] = {0, 0, 0, 0};  // stored minus 1
    std::uint32_t bytes_plane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    std::vector<Ktx2Sample> samples;
};

struct Ktx2Level {
    std::uint32_t width = 0;  // max(1, pixelWidth >> level)
    std::uint32_t height = 0;
    std::uint64_t byte_offset = 0;  // from the start of the file
    std::uint64_t byte_length = 0;  // all layers of the level
    std::uint64_t uncompressed_byte_length = 0;
};

// Everything in a KTX2 file but its texel data.
struct Ktx2Info {
    std::string path;
    std::uint64_t file_size = 0;
    std::uint32_t vk_format = 0;
    std::uint32_t type_size = 0;
    std::uint32_t pixel_width = 0;
    std::uint32_t pixel_height = 0;
    std::uint32_t pixel_depth = 0;
    std::uint32_t layer_count = 0;
    std::uint32_t face_count = 0;
    std::uint32_t level_count = 0;
    std::uint32_t supercompression_scheme = 0;
    std::uint32_t dfd_byte_offset = 0;
    std::uint32_t dfd_byte_length = 0;
    std::uint32_t kvd_byte_offset = 0;
    std::uint32_t kvd_byte_length = 0;
    std::uint64_t sgd_byte_offset = 0;
    std::uint64_t sgd_byte_length = 0;
    std::vector<Ktx2Level> levels;  // level 0 (largest) first, as in the level index
    Ktx2DataFormat data_format;
    // Key/value pairs in file order; values as raw bytes with one trailing NUL removed.
    std::vector<std::pair<std::string, std::string>> key_values;

    // The value of `key`, or nullptr when absent.
    const std::string* find(const std::string& key) const;
};

// Reads and structurally checks any KTX 2.0 file (identifier, header sizes, level index, DFD and
// key/value data inside the file and apart from each other, no key twice) without reading texel
// data and without the leanfade-specific checks of read_ktx2 (so that describe() can show what a
// file from another writer holds). `leanfade info` runs read_ktx2's checks too, before printing.
Ktx2Info inspect_ktx2(const std::string& path);
// inspect_ktx2 on a file's bytes already in memory; Ktx2Info::path is `name`.
Ktx2Info inspect_ktx2_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& name);

// Multi-line human-readable description: header fields, data format, each level's size, offset
// and length, and all key/values (escaped by escape_text: control characters, invalid UTF-8 and
// backslashes as \xHH; each key and value cut after kDescribedTextBytes, ending "..."). Ends
// with a newline.
inline constexpr std::size_t kDescribedTextBytes = 1024;
std::string describe(const Ktx2Info& info);

}  // namespace leanfade::io
