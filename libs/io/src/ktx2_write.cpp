// Writing LEAN maps as KTX2 (leanfade/io/ktx2.hpp): the file plan, the mapped writer, bakes into a
// file.
#include "leanfade/io/ktx2.hpp"

#include "ktx2_internal.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numeric>
#include <optional>
#include <span>
#include <sstream>
#include <utility>

#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/version.hpp"

#include <zstd.h>

namespace leanfade::io {

using namespace ktx2_detail;

namespace {

// Everything of a KTX2 file of `layout` but its level data: the encoded data format descriptor
// and key/value data, and each level's uncompressed length (all layers).
struct Ktx2FilePlan {
    const FormatInfo* format = nullptr;
    std::uint32_t width = 0, height = 0;
    std::uint32_t layer_count = kLayerCount;  // kPlateauLayerCount with the plateau layer
    std::vector<std::uint8_t> key_values;
    std::vector<std::uint64_t> level_lengths;  // level 0 first

    std::uint64_t head_size() const {
        return kHeaderSize + kLevelIndexEntrySize * level_lengths.size() +
               expected_data_format(*format).total_size + key_values.size();
    }
    // Each level's offset in a file whose levels are `byte_lengths` long, stored from the
    // smallest level to the largest (each aligned unless supercompressed); returns the file size.
    std::uint64_t place_levels(const std::vector<std::uint64_t>& byte_lengths, bool supercompressed,
                               std::vector<std::uint64_t>& offsets) const {
        offsets.assign(byte_lengths.size(), 0);
        std::uint64_t end = head_size();
        for (std::size_t level = byte_lengths.size(); level-- > 0;) {
            end = align_up(end, level_alignment(*format, supercompressed));
            offsets[level] = end;
            end += byte_lengths[level];
        }
        return end;
    }
    // The header, level index, DFD and key/value data: a few hundred bytes.
    std::vector<std::uint8_t> head(std::uint32_t scheme, const std::vector<std::uint64_t>& offsets,
                                   const std::vector<std::uint64_t>& byte_lengths) const {
        const std::vector<std::uint8_t> dfd =
            encode_data_format(expected_data_format(*format, scheme != kSchemeNone));
        const auto level_count = std::uint32_t(level_lengths.size());
        const std::uint64_t dfd_offset = kHeaderSize + kLevelIndexEntrySize * level_count;
        const std::uint64_t kvd_offset = dfd_offset + dfd.size();
        std::vector<std::uint8_t> bytes(kIdentifier.begin(), kIdentifier.end());
        append_u32_le(bytes, format->vk_format);
        append_u32_le(bytes, format->type_size);
        append_u32_le(bytes, width);
        append_u32_le(bytes, height);
        append_u32_le(bytes, 0);  // pixelDepth: 2D
        append_u32_le(bytes, layer_count);
        append_u32_le(bytes, 1);  // faceCount
        append_u32_le(bytes, level_count);
        append_u32_le(bytes, scheme);  // supercompressionScheme
        append_u32_le(bytes, std::uint32_t(dfd_offset));
        append_u32_le(bytes, std::uint32_t(dfd.size()));
        append_u32_le(bytes, std::uint32_t(kvd_offset));
        append_u32_le(bytes, std::uint32_t(key_values.size()));
        append_u64_le(bytes, 0);  // sgdByteOffset: Zstandard has no global data
        append_u64_le(bytes, 0);  // sgdByteLength
        for (std::uint32_t level = 0; level < level_count; ++level) {
            append_u64_le(bytes, offsets[level]);
            append_u64_le(bytes, byte_lengths[level]);   // byteLength
            append_u64_le(bytes, level_lengths[level]);  // uncompressedByteLength
        }
        bytes.insert(bytes.end(), dfd.begin(), dfd.end());
        bytes.insert(bytes.end(), key_values.begin(), key_values.end());
        return bytes;
    }
};

Ktx2FilePlan plan_ktx2_file(const std::string& path, const PackedLeanMap& layout, bool check_layers,
                            const char* layout_name = kLeanLayoutName) {
    Ktx2FilePlan plan;
    plan.format = &format_of(layout.storage);
    validate_for_write(path, layout, *plan.format, check_layers);
    plan.width = std::uint32_t(layout.levels.front().width);
    plan.height = std::uint32_t(layout.levels.front().height);

    std::vector<std::pair<std::string, std::string>> key_values = lean_metadata_keys(layout);
    key_values.emplace_back(kKeyOrientation, "rd");
    key_values.emplace_back(
        kKeyWriter,
        layout.generator.empty() ? std::string("leanfade " LEANFADE_VERSION) : layout.generator);
    const bool plateau = layout.has_plateau();
    key_values.emplace_back(kLayoutKey, std::strcmp(layout_name, kLeanLayoutName) == 0
                                            ? lean_layout_name(layout.encoding, plateau)
                                            : layout_name);
    plan.layer_count = std::uint32_t(layout.layer_count());
    std::sort(key_values.begin(), key_values.end());  // by key bytes, as the spec requires
    for (const auto& [key, value] : key_values) append_key_value(plan.key_values, key, value);

    std::uint64_t total = plan.head_size();
    for (const PackedLevel& level : layout.levels) {
        plan.level_lengths.push_back(plan.layer_count *
                                     layer_bytes(*plan.format, std::uint32_t(level.width),
                                                 std::uint32_t(level.height)));
        total += plan.level_lengths.back() + 16;  // with the alignment
    }
    if (total > std::uint64_t(SIZE_MAX)) throw Error(path, "LEAN map too large to write");
    return plan;
}

void check_zstd_level(const std::string& path, int level) {
    if (level < 1 || level > ZSTD_maxCLevel())
        throw Error(path, "Zstandard level " + std::to_string(level) + " is not in 1.." +
                              std::to_string(ZSTD_maxCLevel()));
}

// Zstandard's compressor of LEAN map levels: each level one frame with its content size and
// checksum, on `threads` workers for large levels.
class ZstdCompressor {
  public:
    ZstdCompressor(const std::string& path, int level, int threads)
        : path_(path), threads_(threads), context_(ZSTD_createCCtx()) {
        check_zstd_level(path, level);
        if (!context_) throw Error(path, "cannot allocate a Zstandard compressor");
        ZSTD_CCtx_setParameter(context_.get(), ZSTD_c_compressionLevel, level);
        ZSTD_CCtx_setParameter(context_.get(), ZSTD_c_checksumFlag, 1);
    }

    // The frame of `pieces` one after the other (a level's layers), handed to `sink` in pieces
    // of up to 128 KiB; returns its length.
    template <class Sink>
    std::uint64_t frame(const std::vector<std::span<const std::uint8_t>>& pieces, Sink&& sink) {
        std::size_t size = 0;
        for (const std::span<const std::uint8_t> piece : pieces) size += piece.size();
        ZSTD_CCtx* context = context_.get();
        ZSTD_CCtx_reset(context, ZSTD_reset_session_only);
        // Multithreading pays off from a few MiB on; a library built without it refuses the
        // parameter and compresses on this thread.
        constexpr std::size_t kThreadedBytes = std::size_t(4) << 20;
        ZSTD_CCtx_setParameter(context, ZSTD_c_nbWorkers,
                               threads_ > 1 && size >= kThreadedBytes ? threads_ : 0);
        ZSTD_CCtx_setPledgedSrcSize(context, size);
        out_.resize(ZSTD_CStreamOutSize());
        std::uint64_t length = 0;
        std::size_t index = 0;
        for (const std::span<const std::uint8_t> piece : pieces) {
            const ZSTD_EndDirective end = ++index == pieces.size() ? ZSTD_e_end : ZSTD_e_continue;
            ZSTD_inBuffer in{piece.data(), piece.size(), 0};
            // ZSTD_e_continue: until the piece is consumed; ZSTD_e_end: until the frame is done.
            for (std::size_t remaining = 1; end == ZSTD_e_end ? remaining != 0 : in.pos < in.size;) {
                ZSTD_outBuffer out{out_.data(), out_.size(), 0};
                remaining = ZSTD_compressStream2(context, &out, &in, end);
                if (ZSTD_isError(remaining))
                    throw Error(path_, std::string("Zstandard compression failed: ") +
                                           ZSTD_getErrorName(remaining));
                sink(out_.data(), out.pos);
                length += out.pos;
            }
        }
        return length;
    }

  private:
    struct ContextDeleter {
        void operator()(ZSTD_CCtx* context) const { ZSTD_freeCCtx(context); }
    };
    std::string path_;
    int threads_;
    std::unique_ptr<ZSTD_CCtx, ContextDeleter> context_;
    std::vector<std::uint8_t> out_;
};

}  // namespace

// A supercompressed file's levels, held uncompressed until commit() compresses them.
struct Ktx2Writer::Staging {
    PackedLeanMap layout;  // the metadata and level sizes (no layer data)
    const char* layout_name = kLeanLayoutName;
    WriteOptions options;
    std::unique_ptr<std::uint8_t, decltype(&std::free)> bytes{nullptr, &std::free};
    std::vector<std::uint64_t> level_offsets;  // in `bytes`
};

Ktx2Writer::~Ktx2Writer() = default;

Ktx2Writer::Ktx2Writer(std::string path, const PackedLeanMap& layout, const WriteOptions& options,
                       bool check_layers, const char* layout_name)
    : file_(path, options.durability) {
    Ktx2FilePlan plan = plan_ktx2_file(path, layout, check_layers, layout_name);
    const auto add_targets = [&](std::uint8_t* base, const std::vector<std::uint64_t>& offsets) {
        for (std::size_t level = 0; level < offsets.size(); ++level) {
            // The level's layers one after the other, in the table's order (kLeanLayers).
            const std::uint64_t layer = plan.level_lengths[level] / plan.layer_count;
            PackedLevelTarget target;
            for (std::uint32_t i = 0; i < plan.layer_count; ++i)
                target.slice(kLeanLayers[i].layer) = base + offsets[level] + i * layer;
            targets_.push_back(target);
        }
    };
    if (options.supercompression == Supercompression::Zstandard) {
        check_zstd_level(path, options.zstd_level);  // before the bake, not at commit()
        // The levels are compressed whole at commit(): until then they wait in memory
        // (calloc: pages the bake has not touched cost nothing).
        staging_ = std::make_unique<Staging>();
        std::uint64_t total = 0;
        for (const std::uint64_t length : plan.level_lengths) {
            staging_->level_offsets.push_back(total);
            total += length;
        }
        staging_->bytes.reset(static_cast<std::uint8_t*>(std::calloc(std::size_t(total), 1)));
        if (!staging_->bytes)
            throw Error(path, "cannot allocate " + std::to_string(total) +
                                  " bytes for the levels before compression");
        staging_->options = options;
        staging_->layout_name = layout_name;
        static_cast<PackedLeanMapMetadata&>(staging_->layout) = layout.metadata();
        for (const PackedLevel& level : layout.levels)
            staging_->layout.levels.push_back({level.width, level.height, {}, {}, {}});
        add_targets(staging_->bytes.get(), staging_->level_offsets);
        return;
    }
    // The level data goes straight into the mapped file; the mip padding between levels is left
    // as the zeros a newly reserved file reads as.
    std::vector<std::uint64_t> offsets;
    const std::uint64_t size = plan.place_levels(plan.level_lengths, false, offsets);
    std::uint8_t* output = file_.map(std::size_t(size));
    const std::vector<std::uint8_t> head = plan.head(kSchemeNone, offsets, plan.level_lengths);
    std::memcpy(output, head.data(), head.size());
    add_targets(output, offsets);
}

bool Ktx2Writer::drop_plateau_layer() {
    if (!staging_ || !staging_->layout.has_plateau() || targets_.empty()) return false;
    // Each staged level keeps its layers back to back: the first two are the new level.
    staging_->layout.plateau_epsilon = 0.0f;
    for (PackedLevelTarget& target : targets_) target.plateau = nullptr;
    return true;
}

void Ktx2Writer::commit() {
    targets_.clear();
    if (staging_) {
        // The head's place first (its size does not depend on the levels' lengths), then each
        // level one frame, from the smallest level to the largest, unaligned; then the head.
        const Ktx2FilePlan plan =
            plan_ktx2_file(file_.path(), staging_->layout, false, staging_->layout_name);
        file_.write(std::vector<std::uint8_t>(std::size_t(plan.head_size()), 0));
        ZstdCompressor compressor(file_.path(), staging_->options.zstd_level,
                                  resolve_thread_count(staging_->options.threads));
        std::vector<std::uint64_t> lengths(plan.level_lengths.size()), offsets;
        for (std::size_t level = lengths.size(); level-- > 0;) {
            lengths[level] = compressor.frame(
                {{staging_->bytes.get() + staging_->level_offsets[level],
                  std::size_t(plan.level_lengths[level])}},
                [&](const std::uint8_t* bytes, std::size_t size) { file_.write(bytes, size); });
        }
        staging_->bytes.reset();
        plan.place_levels(lengths, true, offsets);
        const std::vector<std::uint8_t> head = plan.head(kSchemeZstandard, offsets, lengths);
        file_.write_at(0, head.data(), head.size());
        staging_.reset();
    }
    file_.commit();
}

Ktx2FileSink::Ktx2FileSink(std::string path, const WriteOptions& write_options,
                           const ReadOptions& read_options)
    : path_(std::move(path)), write_options_(write_options), read_options_(read_options) {}

Ktx2FileSink::~Ktx2FileSink() = default;

std::vector<PackedLevelTarget> Ktx2FileSink::open(const PackedLeanMap& layout, int) {
    // A bake that is not kept (the first of `--bits auto`) is discarded unwritten.
    writer_.reset();
    writer_ = std::make_unique<Ktx2Writer>(path_, layout, write_options_);
    return writer_->targets();
}

void Ktx2FileSink::finish(PackedBakeResult&, bool drop_plateau) {
    // Nothing flat: the file keeps no layer of zeros (a third of its bytes). A supercompressed
    // file is written without it; an uncompressed one, whose size was fixed, is written again.
    const bool dropped = drop_plateau && writer_->drop_plateau_layer();
    writer_->commit();
    writer_.reset();
    if (drop_plateau && !dropped) {
        PackedLeanMap map = read_ktx2(path_, read_options_);
        remove_plateau_layer(map);
        write_ktx2(path_, map, write_options_);
    }
}

std::vector<std::uint8_t> write_ktx2_to_memory(const PackedLeanMap& map, const std::string& name,
                                               const WriteOptions& options) {
    const Ktx2FilePlan plan = plan_ktx2_file(name, map, true);
    const bool zstd = options.supercompression == Supercompression::Zstandard;
    const auto layers = [&](const PackedLevel& packed) {
        std::vector<std::span<const std::uint8_t>> spans;
        for (const LeanLayerInfo& row : kLeanLayers)
            if (map.has_layer(row.layer)) spans.emplace_back(packed.slice(row.layer));
        return spans;
    };
    // Supercompressed: each level's frame, then the file; else the layers straight into it.
    std::vector<std::vector<std::uint8_t>> frames;
    std::vector<std::uint64_t> lengths = plan.level_lengths;
    if (zstd) {
        ZstdCompressor compressor(name, options.zstd_level, resolve_thread_count(options.threads));
        for (std::size_t level = 0; level < map.levels.size(); ++level) {
            std::vector<std::uint8_t>& frame = frames.emplace_back();
            lengths[level] = compressor.frame(
                layers(map.levels[level]), [&](const std::uint8_t* bytes, std::size_t size) {
                    frame.insert(frame.end(), bytes, bytes + size);
                });
        }
    }
    std::vector<std::uint64_t> offsets;
    const std::uint64_t size = plan.place_levels(lengths, zstd, offsets);
    std::vector<std::uint8_t> file(std::size_t(size), 0);  // mip padding: zeros
    const std::vector<std::uint8_t> head =
        plan.head(zstd ? kSchemeZstandard : kSchemeNone, offsets, lengths);
    std::copy(head.begin(), head.end(), file.begin());
    for (std::size_t level = 0; level < map.levels.size(); ++level) {
        auto at = file.begin() + std::ptrdiff_t(offsets[level]);
        if (zstd) {
            std::copy(frames[level].begin(), frames[level].end(), at);
            continue;
        }
        for (const std::span<const std::uint8_t> layer : layers(map.levels[level]))
            at = std::copy(layer.begin(), layer.end(), at);
    }
    return file;
}

namespace {

void write_ktx2_as(const std::string& path, const PackedLeanMap& map, const WriteOptions& options,
                   const char* layout_name) {
    Ktx2Writer writer(path, map, options, true, layout_name);
    const std::vector<PackedLevelTarget>& targets = writer.targets();
    // Copied from the map in chunks handed to the threads (no assembled copy of the whole file).
    struct Chunk {
        const std::uint8_t* source;
        std::uint8_t* destination;
        std::size_t size;
    };
    constexpr std::size_t kChunkBytes = std::size_t(4) << 20;
    std::vector<Chunk> chunks;
    for (std::size_t level = 0; level < map.levels.size(); ++level) {
        const PackedLevel& packed = map.levels[level];
        for (const LeanLayerInfo& row : kLeanLayers) {
            if (!map.has_layer(row.layer)) continue;
            const std::vector<std::uint8_t>& source = packed.slice(row.layer);
            std::uint8_t* destination = targets[level].slice(row.layer);
            for (std::size_t first = 0; first < source.size(); first += kChunkBytes) {
                chunks.push_back({source.data() + first, destination + first,
                                  std::min(kChunkBytes, source.size() - first)});
            }
        }
    }
    parallel_for_dynamic(int(chunks.size()), options.threads, 1, [&](int, int first, int last) {
        for (int i = first; i < last; ++i) {
            const Chunk& chunk = chunks[std::size_t(i)];
            std::memcpy(chunk.destination, chunk.source, chunk.size);
        }
    });
    writer.commit();
}

}  // namespace

void write_ktx2(const std::string& path, const PackedLeanMap& map, const WriteOptions& options) {
    write_ktx2_as(path, map, options, kLeanLayoutName);
}

void write_cross_term_ktx2(const std::string& path, const PackedLeanMap& map,
                           const WriteOptions& options) {
    write_ktx2_as(path, map, options, kCrossTermLayoutName);
}

}  // namespace leanfade::io
