// Inspecting and reading KTX2 LEAN maps (leanfade/io/ktx2.hpp): every header field, range and texel
// checked.
#include "leanfade/io/ktx2.hpp"

#include "ktx2_internal.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <optional>
#include <memory>
#include <span>
#include <sstream>

#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/io/detail/atomic_file.hpp"

#include <zstd.h>

namespace leanfade::io {

using namespace ktx2_detail;

namespace {

// The leanfade-specific header checks, run before the level index, DFD or key/value data are
// read (so that absurd sizes are refused before anything is allocated for them).
void validate_lean_header(const std::string& path, const Ktx2Info& info,
                          const ReadOptions& options) {
    const FormatInfo* format = find_format(info.vk_format);
    if (format == nullptr) {
        throw Error(path, "unsupported vkFormat " + std::to_string(info.vk_format) +
                              " (expected 37, 91, 97 or 109)");
    }
    if (info.type_size != format->type_size) {
        throw Error(
            path, "typeSize " + std::to_string(info.type_size) + " does not match " + format->name);
    }
    detail::check_dimensions(path, info.pixel_width, info.pixel_height, options.max_dimension);
    if (info.pixel_depth != 0) {
        throw Error(path, "pixelDepth " + std::to_string(info.pixel_depth) + " (a LEAN map is 2D)");
    }
    if (info.layer_count != kLayerCount && info.layer_count != kPlateauLayerCount) {
        throw Error(path, "layerCount " + std::to_string(info.layer_count) +
                              " (a LEAN map has 2 layers, lean1 and lean2, or 3 with the plateau "
                              "layer)");
    }
    if (info.face_count != 1) {
        throw Error(path, "faceCount " + std::to_string(info.face_count) + " (expected 1)");
    }
    if (info.supercompression_scheme != kSchemeNone &&
        info.supercompression_scheme != kSchemeZstandard) {
        throw Error(path, "supercompressionScheme " + std::to_string(info.supercompression_scheme) +
                              " (" + supercompression_name(info.supercompression_scheme) +
                              ") is not supported (a LEAN map is stored plain or with Zstandard)");
    }
    if (info.supercompression_scheme == kSchemeZstandard && info.sgd_byte_length != 0)
        throw Error(path, "Zstandard supercompression has no global data, but sgdByteLength is " +
                              std::to_string(info.sgd_byte_length));
    const std::uint32_t chain = full_chain_length(info.pixel_width, info.pixel_height);
    if (info.level_count == 0) {
        throw Error(path, "levelCount 0 (MIP levels generated at load) is not supported");
    }
    if (info.level_count > chain) {
        throw Error(path, "levelCount " + std::to_string(info.level_count) + " exceeds the " +
                              std::to_string(chain) + " levels of a " +
                              std::to_string(info.pixel_width) + "x" +
                              std::to_string(info.pixel_height) + " MIP chain");
    }
    if (info.level_count < chain) {
        throw Error(path, "levelCount " + std::to_string(info.level_count) +
                              " is a partial MIP chain (a LEAN map of " +
                              std::to_string(info.pixel_width) + "x" +
                              std::to_string(info.pixel_height) + " has all " +
                              std::to_string(chain) + " levels)");
    }
}

// Float storages can hold NaN and infinity, which no bake writes and no renderer can use: the
// first one is refused, naming its level, layer and texel.
void check_finite_texels(const std::string& path, const FormatInfo& format,
                         const PackedLevel& level, std::uint32_t level_number) {
    if (!format.is_float) return;
    for (const LeanLayerInfo& layer : kLeanLayers) {
        const std::vector<std::uint8_t>& bytes = level.slice(layer.layer);
        const std::size_t values = bytes.size() / format.type_size;
        for (std::size_t i = 0; i < values; ++i) {
            bool finite = true, nan = false;
            if (format.type_size == 2) {
                const std::uint16_t bits = detail::load_u16_le(bytes.data() + 2 * i);
                finite = (bits & 0x7C00u) != 0x7C00u;
                nan = !finite && (bits & 0x03FFu) != 0;
            } else {
                const std::uint32_t bits = load_u32_le(bytes.data() + 4 * i);
                finite = (bits & 0x7F800000u) != 0x7F800000u;
                nan = !finite && (bits & 0x007FFFFFu) != 0;
            }
            if (finite) continue;
            const std::size_t texel = i / 4;
            throw Error(path, std::string(nan ? "NaN" : "infinity") + " in level " +
                                  std::to_string(level_number) + " of " + std::string(layer.label) +
                                  " at texel (" + std::to_string(texel % std::size_t(level.width)) +
                                  ", " + std::to_string(texel / std::size_t(level.width)) + ")");
        }
    }
}

// Every part of the file (the header with the level index, the data format descriptor, the
// key/value data, the supercompression global data and each level) must lie apart from every
// other: a level inside the header or two levels sharing bytes are refused.
void check_no_overlaps(const std::string& path, const Ktx2Info& info) {
    struct Part {
        std::uint64_t offset, length;
        std::string name;
    };
    std::vector<Part> parts = {
        {0, kHeaderSize + kLevelIndexEntrySize * std::uint64_t(info.levels.size()),
         "the header and level index"},
        {info.dfd_byte_offset, info.dfd_byte_length, "the data format descriptor"},
        {info.kvd_byte_offset, info.kvd_byte_length, "the key/value data"},
        {info.sgd_byte_offset, info.sgd_byte_length, "the supercompression global data"}};
    for (std::size_t level = 0; level < info.levels.size(); ++level) {
        parts.push_back({info.levels[level].byte_offset, info.levels[level].byte_length,
                         "level " + std::to_string(level) + " data"});
    }
    std::erase_if(parts, [](const Part& part) { return part.length == 0; });
    std::stable_sort(parts.begin(), parts.end(),
                     [](const Part& a, const Part& b) { return a.offset < b.offset; });
    for (std::size_t i = 1; i < parts.size(); ++i) {
        const Part& before = parts[i - 1];
        const Part& part = parts[i];
        if (part.offset < before.offset + before.length) {  // both inside the file: no overflow
            throw Error(path, part.name + " (offset " + std::to_string(part.offset) + ", length " +
                                  std::to_string(part.length) + ") overlaps " + before.name +
                                  " (offset " + std::to_string(before.offset) + ", length " +
                                  std::to_string(before.length) + ")");
        }
    }
}

// `strict`: also run validate_lean_header (read_ktx2).
Ktx2Info inspect_open_file(const detail::InputFile& file, const ReadOptions* strict) {
    const std::string& path = file.path();
    Ktx2Info info;
    info.path = path;
    info.file_size = file.size();

    std::array<std::uint8_t, kHeaderSize> header{};
    const std::size_t identifier_bytes = std::size_t(std::min<std::uint64_t>(file.size(), 12));
    file.read_at(0, header.data(), identifier_bytes, "truncated KTX2 identifier");
    if (std::memcmp(header.data(), kIdentifier.data(), identifier_bytes) != 0) {
        throw Error(path, "not a KTX 2.0 file (bad identifier)");
    }
    if (identifier_bytes < kIdentifier.size()) throw Error(path, "truncated KTX2 identifier");
    file.read_at(0, header.data(), kHeaderSize, "truncated KTX2 header");

    const std::uint8_t* field = header.data() + kIdentifier.size();
    info.vk_format = load_u32_le(field + 0);
    info.type_size = load_u32_le(field + 4);
    info.pixel_width = load_u32_le(field + 8);
    info.pixel_height = load_u32_le(field + 12);
    info.pixel_depth = load_u32_le(field + 16);
    info.layer_count = load_u32_le(field + 20);
    info.face_count = load_u32_le(field + 24);
    info.level_count = load_u32_le(field + 28);
    info.supercompression_scheme = load_u32_le(field + 32);
    info.dfd_byte_offset = load_u32_le(field + 36);
    info.dfd_byte_length = load_u32_le(field + 40);
    info.kvd_byte_offset = load_u32_le(field + 44);
    info.kvd_byte_length = load_u32_le(field + 48);
    info.sgd_byte_offset = load_u64_le(field + 52);
    info.sgd_byte_length = load_u64_le(field + 60);

    if (strict != nullptr) validate_lean_header(path, info, *strict);
    if (info.level_count > kMaxLevelCount) {
        throw Error(path, "levelCount " + std::to_string(info.level_count) + " is more than " +
                              std::to_string(kMaxLevelCount));
    }
    // Any KTX2: at most one level per halving of the largest side; checked before the level
    // index is read, so that a count past the chain is named as such (not as the garbage
    // offsets the extra index entries would hold).
    const std::uint32_t chain =
        full_chain_length(std::max(info.pixel_width, info.pixel_depth), info.pixel_height);
    if (info.level_count > chain) {
        throw Error(path, "levelCount " + std::to_string(info.level_count) + " exceeds the " +
                              std::to_string(chain) + " levels of a " +
                              std::to_string(info.pixel_width) + "x" +
                              std::to_string(info.pixel_height) +
                              (info.pixel_depth > 1 ? "x" + std::to_string(info.pixel_depth) : "") +
                              " MIP chain");
    }
    const std::uint32_t index_entries = std::max<std::uint32_t>(1, info.level_count);
    std::vector<std::uint8_t> index(index_entries * kLevelIndexEntrySize);
    file.read_at(kHeaderSize, index.data(), index.size(), "truncated KTX2 level index");
    for (std::uint32_t level = 0; level < index_entries; ++level) {
        const std::uint8_t* entry = index.data() + level * kLevelIndexEntrySize;
        Ktx2Level level_info;
        level_info.width = level_size(info.pixel_width, level);
        level_info.height = level_size(info.pixel_height, level);
        level_info.byte_offset = load_u64_le(entry);
        level_info.byte_length = load_u64_le(entry + 8);
        level_info.uncompressed_byte_length = load_u64_le(entry + 16);
        if (!inside(level_info.byte_offset, level_info.byte_length, info.file_size)) {
            throw Error(path, "level " + std::to_string(level) + " data (offset " +
                                  std::to_string(level_info.byte_offset) + ", length " +
                                  std::to_string(level_info.byte_length) +
                                  ") runs past the end of the file (" +
                                  std::to_string(info.file_size) + " bytes)");
        }
        info.levels.push_back(level_info);
    }

    if (info.dfd_byte_length == 0) throw Error(path, "missing data format descriptor");
    if (!inside(info.dfd_byte_offset, info.dfd_byte_length, info.file_size)) {
        throw Error(path, "data format descriptor runs past the end of the file");
    }
    if (!inside(info.kvd_byte_offset, info.kvd_byte_length, info.file_size)) {
        throw Error(path, "key/value data runs past the end of the file");
    }
    if (!inside(info.sgd_byte_offset, info.sgd_byte_length, info.file_size)) {
        throw Error(path, "supercompression global data runs past the end of the file");
    }
    check_no_overlaps(path, info);

    std::vector<std::uint8_t> dfd(info.dfd_byte_length);
    file.read_at(info.dfd_byte_offset, dfd.data(), dfd.size(), "truncated data format descriptor");
    info.data_format = decode_data_format(path, dfd);

    std::vector<std::uint8_t> kvd(info.kvd_byte_length);
    file.read_at(info.kvd_byte_offset, kvd.data(), kvd.size(), "truncated key/value data");
    info.key_values = decode_key_values(path, kvd);
    return info;
}

void validate_data_format(const std::string& path, const Ktx2DataFormat& actual,
                          const FormatInfo& format, bool supercompressed) {
    const Ktx2DataFormat expected = expected_data_format(format, supercompressed);
    const auto fail = [&](const std::string& what) {
        throw Error(path, "data format descriptor does not describe " + std::string(format.name) +
                              " (" + what + ")");
    };
    if (actual.vendor_id != 0 || actual.descriptor_type != 0) fail("not a basic descriptor");
    if (actual.color_model != expected.color_model) fail("colour model is not RGBSDA");
    if (actual.transfer_function != expected.transfer_function) fail("transfer is not LINEAR");
    if (actual.bytes_plane[0] != expected.bytes_plane[0])
        fail("bytesPlane0 " + std::to_string(actual.bytes_plane[0]) + ", expected " +
             std::to_string(expected.bytes_plane[0]) +
             (supercompressed ? " for supercompressed data" : ""));
    for (int i = 0; i < 4; ++i) {
        if (actual.texel_block_dimensions[i] != 0) fail("texel block is not 1x1x1x1");
    }
    if (actual.samples.size() != expected.samples.size()) fail("sample count");
    for (std::size_t i = 0; i < expected.samples.size(); ++i) {
        const Ktx2Sample& a = actual.samples[i];
        const Ktx2Sample& e = expected.samples[i];
        if (a.bit_offset != e.bit_offset || a.bit_length != e.bit_length ||
            a.channel_id != e.channel_id || a.qualifiers != e.qualifiers ||
            a.sample_lower != e.sample_lower || a.sample_upper != e.sample_upper) {
            fail("sample " + std::to_string(i));
        }
    }
}

const std::string& required_key(const std::string& path, const Ktx2Info& info, const char* key) {
    const std::string* value = info.find(key);
    if (value == nullptr) throw Error(path, std::string("missing key ") + key);
    return *value;
}

// Decompresses one supercompressed level (`frame`, a Zstandard frame) into its layers of
// `layer_size` bytes each (empty on entry), which must come out exactly: corrupt, short or long
// data is refused, naming the level. Memory grows with the data that actually decompresses (a
// hostile frame that declares a large level and holds garbage fails in its first block).
void inflate_level(const std::string& path, std::uint32_t level, ZSTD_DCtx* decompressor,
                   const std::vector<std::uint8_t>& frame, std::uint64_t layer_size,
                   std::span<std::vector<std::uint8_t>* const> layers) {
    const auto fail = [&](const std::string& cause) {
        throw Error(path, "level " + std::to_string(level) + ": " + cause);
    };
    const std::uint64_t expected = layer_size * layers.size();
    const unsigned long long declared = ZSTD_getFrameContentSize(frame.data(), frame.size());
    if (declared == ZSTD_CONTENTSIZE_ERROR) fail("not Zstandard data");
    if (declared == ZSTD_CONTENTSIZE_UNKNOWN) fail("its Zstandard frame does not declare its size");
    if (declared != expected)
        fail("its Zstandard frame holds " + std::to_string(declared) + " bytes, expected " +
             std::to_string(expected));
    ZSTD_DCtx_reset(decompressor, ZSTD_reset_session_only);
    ZSTD_inBuffer in{frame.data(), frame.size(), 0};
    std::vector<std::uint8_t> chunk(std::size_t(1) << 20);
    std::size_t pending = 1;  // ZSTD_decompressStream's hint: 0 once a frame is complete
    for (std::vector<std::uint8_t>* layer : layers) {
        layer->reserve(std::size_t(layer_size));  // address space only until written
        while (layer->size() < layer_size) {
            const std::size_t want =
                std::size_t(std::min<std::uint64_t>(chunk.size(), layer_size - layer->size()));
            ZSTD_outBuffer out{chunk.data(), want, 0};
            const std::size_t before_in = in.pos;
            pending = ZSTD_decompressStream(decompressor, &out, &in);
            if (ZSTD_isError(pending))
                fail(std::string("corrupt Zstandard data (") + ZSTD_getErrorName(pending) + ")");
            if (in.pos == before_in && out.pos == 0)
                fail("its Zstandard data ends before the level's " + std::to_string(expected) +
                     " bytes");
            layer->insert(layer->end(), chunk.data(), chunk.data() + out.pos);
        }
    }
    // The frame must end here (its checksum verified) with nothing after it.
    while (pending != 0) {
        ZSTD_outBuffer out{chunk.data(), 1, 0};
        const std::size_t before_in = in.pos;
        pending = ZSTD_decompressStream(decompressor, &out, &in);
        if (ZSTD_isError(pending))
            fail(std::string("corrupt Zstandard data (") + ZSTD_getErrorName(pending) + ")");
        if (out.pos != 0)
            fail("its Zstandard data holds more than the level's " + std::to_string(expected) +
                 " bytes");
        if (pending != 0 && in.pos == before_in) fail("its Zstandard frame is truncated");
    }
    if (in.pos != in.size)
        fail(std::to_string(in.size - in.pos) + " bytes after its Zstandard frame");
}

PackedLeanMap read_open_file(const detail::InputFile& file, const ReadOptions& options,
                             const char* layout_name = kLeanLayoutName) {
    const std::string& path = file.path();
    const Ktx2Info info = inspect_open_file(file, &options);
    const FormatInfo* format = find_format(info.vk_format);
    const bool zstd = info.supercompression_scheme == kSchemeZstandard;
    for (std::uint32_t level = 0; level < info.level_count; ++level) {
        const Ktx2Level& entry = info.levels[level];
        const std::uint64_t expected =
            info.layer_count * layer_bytes(*format, entry.width, entry.height);
        // A Zstandard frame is at least a few bytes and at most ZSTD_compressBound long.
        const bool length_ok =
            zstd ? entry.byte_length > 0 && entry.byte_length <= ZSTD_compressBound(expected)
                 : entry.byte_length == expected;
        if (!length_ok || entry.uncompressed_byte_length != expected) {
            throw Error(path, "level " + std::to_string(level) + " byteLength " +
                                  std::to_string(entry.byte_length) + " / uncompressed " +
                                  std::to_string(entry.uncompressed_byte_length) + ", expected " +
                                  (zstd ? "a Zstandard frame / " : std::to_string(expected) + " / ") +
                                  std::to_string(expected));
        }
        if (entry.byte_offset % level_alignment(*format, zstd) != 0) {
            throw Error(path, "level " + std::to_string(level) + " offset " +
                                  std::to_string(entry.byte_offset) + " is not aligned to " +
                                  std::to_string(level_alignment(*format)) + " bytes");
        }
    }
    validate_data_format(path, info.data_format, *format, zstd);

    PackedLeanMap map;
    map.storage = format->storage;
    const std::string& layout = required_key(path, info, kLayoutKey);
    if (layout == kCrossTermLayoutName && layout != layout_name)
        throw Error(path, "is a cross-term texture (bake --cross-terms), not a LEAN map");
    const bool signed_layout =
        layout == kLeanSignedLayoutName || layout == kLeanSignedPlateauLayoutName;
    const bool lean_layout = is_lean_layout_name(layout);
    if (lean_layout && std::string(layout_name) != kLeanLayoutName)
        throw Error(path, "is a LEAN map, not a cross-term texture");
    if (!lean_layout && layout != layout_name) {
        throw Error(path, "unsupported " + std::string(kLayoutKey) + " '" + escape_text(layout) +
                              "' (expected '" + layout_name + "')");
    }
    if (signed_layout && map.storage != Storage::Float16 && map.storage != Storage::Float32)
        throw Error(path, std::string(kLayoutKey) + " '" + layout +
                              "' (signed values) needs a float vkFormat, not " +
                              vk_format_name(info.vk_format));
    map.encoding = signed_layout ? LeanEncoding::Signed : LeanEncoding::Offset;
    const std::uint32_t layers =
        layout == kLeanPlateauLayoutName || layout == kLeanSignedPlateauLayoutName
            ? kPlateauLayerCount
            : kLayerCount;
    if (info.layer_count != layers)
        throw Error(path, "layerCount " + std::to_string(info.layer_count) + " does not match " +
                              kLayoutKey + " '" + layout + "' (" + std::to_string(layers) +
                              " layers)");
    map.scale = parse_float(path, kScaleKey, required_key(path, info, kScaleKey));
    if (!(map.scale > 0.0f)) throw Error(path, std::string(kScaleKey) + " must be > 0");
    if (map.scale > kMaxLeanScale)
        throw Error(path, std::string(kScaleKey) + " " + format_float(map.scale) +
                              " exceeds the largest sc a bake writes (" +
                              format_float(kMaxLeanScale) + ": slopes are at most 1e6)");
    const std::string& baked = required_key(path, info, kRoughnessBakedKey);
    if (baked != "0" && baked != "1") {
        throw Error(path, "bad " + std::string(kRoughnessBakedKey) + " value '" +
                              escape_text(baked) + "' (expected 0 or 1)");
    }
    map.roughness_baked = baked == "1";
    map.baked_shininess =
        parse_float(path, kBakedShininessKey, required_key(path, info, kBakedShininessKey));
    if (map.baked_shininess < 0.0f) {
        throw Error(path, std::string(kBakedShininessKey) + " must be >= 0");
    }
    const std::string& convention = required_key(path, info, kNormalConventionKey);
    if (convention == "opengl") {
        map.source_convention = NormalConvention::OpenGL;
    } else if (convention == "directx") {
        map.source_convention = NormalConvention::DirectX;
    } else {
        throw Error(path, "bad " + std::string(kNormalConventionKey) + " value '" +
                              escape_text(convention) + "' (expected opengl or directx)");
    }
    for (const auto& [key, count] :
         {std::pair{kPaddingTexelsKey, &map.normal_repairs.padding_texels},
          std::pair{kRaisedTexelsKey, &map.normal_repairs.raised_texels}}) {
        if (const std::string* text = info.find(key); text != nullptr)
            *count = parse_count(path, key, *text);
    }
    if (const std::string* warning = info.find(kConventionWarningKey); warning != nullptr) {
        if (*warning != "other")
            throw Error(path, "bad " + std::string(kConventionWarningKey) + " value '" +
                                  escape_text(*warning) + "' (expected other)");
        map.source_looks_flipped = true;
    }
    if (const std::string* orientation = info.find(kKeyOrientation);
        orientation != nullptr && *orientation != "rd") {
        throw Error(path, "unsupported KTXorientation '" + escape_text(*orientation) +
                              "' (rows must be stored top first: rd)");
    }
    if (const std::string* writer = info.find(kKeyWriter); writer != nullptr) {
        map.generator = *writer;
    }
    if (layers == kPlateauLayerCount) {
        map.plateau_epsilon =
            parse_float(path, kPlateauEpsilonKey, required_key(path, info, kPlateauEpsilonKey));
        if (!(map.plateau_epsilon > 0.0f))
            throw Error(path, std::string(kPlateauEpsilonKey) + " must be > 0");
    }

    // Every level was checked to lie inside the file with its exact size (or, supercompressed,
    // its declared size, which max_dimension bounds): the allocations below are bounded.
    std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> decompressor(nullptr, &ZSTD_freeDCtx);
    for (std::uint32_t level = 0; level < info.level_count; ++level) {
        const Ktx2Level& entry = info.levels[level];
        const std::uint64_t layer_size = entry.uncompressed_byte_length / layers;
        PackedLevel packed;
        packed.width = int(entry.width);
        packed.height = int(entry.height);
        std::vector<std::uint8_t>* targets[kLeanLayerCount];  // the layers in the table's order
        for (std::size_t i = 0; i < kLeanLayerCount; ++i)
            targets[i] = &packed.slice(kLeanLayers[i].layer);
        if (zstd) {
            if (!decompressor) decompressor.reset(ZSTD_createDCtx());
            if (!decompressor) throw Error(path, "cannot allocate a Zstandard decompressor");
            std::vector<std::uint8_t> frame(std::size_t(entry.byte_length));
            file.read_at(entry.byte_offset, frame.data(), frame.size(), "truncated level data");
            inflate_level(path, level, decompressor.get(), frame, layer_size,
                          {targets, targets + layers});
        } else {
            for (std::uint32_t layer = 0; layer < layers; ++layer) {
                targets[layer]->resize(std::size_t(layer_size));
                file.read_at(entry.byte_offset + layer * layer_size, targets[layer]->data(),
                             targets[layer]->size(), "truncated level data");
            }
        }
        check_finite_texels(path, *format, packed, level);
        map.levels.push_back(std::move(packed));
    }
    return map;
}

}  // namespace

Ktx2Info inspect_ktx2(const std::string& path) {
    const detail::InputFile file(path);
    return inspect_open_file(file, nullptr);
}

Ktx2Info inspect_ktx2_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& name) {
    const detail::InputFile file(name, bytes.data(), bytes.size());
    return inspect_open_file(file, nullptr);
}

PackedLeanMap read_ktx2(const std::string& path, const ReadOptions& options) {
    const detail::InputFile file(path);
    return read_open_file(file, options);
}

PackedLeanMap read_cross_term_ktx2(const std::string& path, const ReadOptions& options) {
    const detail::InputFile file(path);
    return read_open_file(file, options, kCrossTermLayoutName);
}

PackedLeanMap read_ktx2_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& name,
                                    const ReadOptions& options) {
    const detail::InputFile file(name, bytes.data(), bytes.size());
    return read_open_file(file, options);
}

}  // namespace leanfade::io
