// Writing LEAN maps as KTX2 (leanfade/io/ktx2.hpp): the file plan, the mapped writer, bakes into a
// file.
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
#include <sstream>
#include <utility>

#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/input_text.hpp"
#include "leanfade/core/parallel.hpp"
#include "leanfade/core/plateau.hpp"
#include "leanfade/io/atomic_file.hpp"
#include "leanfade/version.hpp"

namespace leanfade::io {

using namespace ktx2_detail;

namespace {

// Where everything goes in a KTX2 file of `layout`: the bytes of its header, level index, DFD and
// key/value data, and each level's offset and length (all layers) in a file of `size` bytes.
struct Ktx2FilePlan {
    std::vector<std::uint8_t> head;
    std::vector<std::uint64_t> level_offsets;
    std::vector<std::uint64_t> level_lengths;
    std::uint64_t size = 0;
    std::uint32_t layer_count = kLayerCount;  // kPlateauLayerCount with the plateau layer
};

Ktx2FilePlan plan_ktx2_file(const std::string& path, const PackedLeanMap& layout, bool check_layers,
                            const char* layout_name = kLeanLayoutName) {
    const FormatInfo& format = format_of(layout.storage);
    validate_for_write(path, layout, format, check_layers);
    const auto level_count = std::uint32_t(layout.levels.size());
    const PackedLevel& top = layout.levels.front();

    std::vector<std::pair<std::string, std::string>> key_values = lean_metadata_keys(layout);
    key_values.emplace_back(kKeyOrientation, "rd");
    key_values.emplace_back(
        kKeyWriter,
        layout.generator.empty() ? std::string("leanfade " LEANFADE_VERSION) : layout.generator);
    const bool plateau = layout.has_plateau();
    key_values.emplace_back(kLayoutKey, std::strcmp(layout_name, kLeanLayoutName) == 0
                                            ? lean_layout_name(layout.encoding, plateau)
                                            : layout_name);
    const std::uint32_t layer_count = plateau ? kPlateauLayerCount : kLayerCount;
    std::sort(key_values.begin(), key_values.end());  // by key bytes, as the spec requires
    std::vector<std::uint8_t> key_value_bytes;
    for (const auto& [key, value] : key_values) append_key_value(key_value_bytes, key, value);

    const std::vector<std::uint8_t> dfd_bytes = encode_data_format(expected_data_format(format));
    const std::uint64_t dfd_offset = kHeaderSize + kLevelIndexEntrySize * level_count;
    const std::uint64_t kvd_offset = dfd_offset + dfd_bytes.size();

    // Level data from the smallest level to the largest, each aligned.
    std::vector<std::uint64_t> level_offsets(level_count), level_lengths(level_count);
    std::uint64_t end = kvd_offset + key_value_bytes.size();
    for (std::uint32_t level = level_count; level-- > 0;) {
        end = align_up(end, level_alignment(format));
        level_offsets[level] = end;
        level_lengths[level] = layer_count * layer_bytes(format, std::uint32_t(layout.levels[level].width),
                                               std::uint32_t(layout.levels[level].height));
        end += level_lengths[level];
    }
    if (end > std::uint64_t(SIZE_MAX)) throw Error(path, "LEAN map too large to write");

    // Header, level index, DFD and key/value data: a few hundred bytes.
    std::vector<std::uint8_t> bytes(kIdentifier.begin(), kIdentifier.end());
    append_u32_le(bytes, format.vk_format);
    append_u32_le(bytes, format.type_size);
    append_u32_le(bytes, std::uint32_t(top.width));
    append_u32_le(bytes, std::uint32_t(top.height));
    append_u32_le(bytes, 0);  // pixelDepth: 2D
    append_u32_le(bytes, layer_count);
    append_u32_le(bytes, 1);  // faceCount
    append_u32_le(bytes, level_count);
    append_u32_le(bytes, 0);  // supercompressionScheme: none
    append_u32_le(bytes, std::uint32_t(dfd_offset));
    append_u32_le(bytes, std::uint32_t(dfd_bytes.size()));
    append_u32_le(bytes, std::uint32_t(kvd_offset));
    append_u32_le(bytes, std::uint32_t(key_value_bytes.size()));
    append_u64_le(bytes, 0);  // sgdByteOffset
    append_u64_le(bytes, 0);  // sgdByteLength
    for (std::uint32_t level = 0; level < level_count; ++level) {
        append_u64_le(bytes, level_offsets[level]);
        append_u64_le(bytes, level_lengths[level]);  // byteLength
        append_u64_le(bytes, level_lengths[level]);  // uncompressedByteLength
    }
    bytes.insert(bytes.end(), dfd_bytes.begin(), dfd_bytes.end());
    bytes.insert(bytes.end(), key_value_bytes.begin(), key_value_bytes.end());

    return {std::move(bytes), std::move(level_offsets), std::move(level_lengths), end, layer_count};
}

}  // namespace

Ktx2Writer::Ktx2Writer(std::string path, const PackedLeanMap& layout, const WriteOptions& options,
                       bool check_layers, const char* layout_name)
    : file_(path, options.durability) {
    const Ktx2FilePlan plan = plan_ktx2_file(path, layout, check_layers, layout_name);
    // The level data goes straight into the mapped file; the mip padding between levels is left
    // as the zeros a newly reserved file reads as.
    std::uint8_t* output = file_.map(std::size_t(plan.size));
    std::memcpy(output, plan.head.data(), plan.head.size());
    for (std::size_t level = 0; level < plan.level_offsets.size(); ++level) {
        std::uint8_t* lean1 = output + plan.level_offsets[level];
        const std::uint64_t layer = plan.level_lengths[level] / plan.layer_count;
        targets_.push_back({lean1, lean1 + layer,
                            plan.layer_count == kPlateauLayerCount ? lean1 + 2 * layer : nullptr});
    }
}

void Ktx2Writer::commit() {
    targets_.clear();
    file_.commit();
}

PackedBakeResult bake_to_ktx2(const std::string& path, const std::variant<Image, UnormImage>& input,
                              BakeSource source, const BakeOptions& options, Storage storage,
                              const std::string& generator, const std::string& source_name,
                              const WriteOptions& write_options, const MomentRunSink& moments) {
    std::optional<Ktx2Writer> writer;
    const auto open_output = [&](const PackedLeanMap& layout) {
        writer.emplace(path, layout, write_options);
        return writer->targets();
    };
    PackedBakeResult baked = std::visit(
        [&](const auto& image) {
            return bake_packed_to(open_output, image, source, options, storage, generator,
                                  source_name, moments);
        },
        input);
    writer->commit();
    return baked;
}

PackedBakeResult bake_image_to_ktx2(const std::string& path,
                                    const std::variant<Image, UnormImage>& input,
                                    BakeSource source, const BakeOptions& options,
                                    StoragePolicy storage, const std::string& generator,
                                    const std::string& source_name,
                                    const WriteOptions& write_options,
                                    const ReadOptions& read_options,
                                    const MomentRunSink& moments) {
    const auto [width, height] = std::visit(
        [](const auto& image) { return std::pair<int, int>(image.width, image.height); }, input);
    PackedBakeResult result = bake_with_auto_storage(
        storage.storage, storage.automatic, width, height,
        [&](Storage s, const MomentRunSink& probe) {
            return bake_to_ktx2(path, input, source, options, s, generator, source_name,
                                write_options, both_sinks(moments, probe));
        });
    if (result.packed.has_plateau() && result.summary.plateau_fraction == 0.0f) {
        // Nothing flat: the file keeps no layer of zeros (a third of its bytes).
        PackedLeanMap map = read_ktx2(path, read_options);
        remove_plateau_layer(map);
        write_ktx2(path, map, write_options);
        result.packed.plateau_epsilon = 0.0f;
    }
    return result;
}

std::vector<std::uint8_t> write_ktx2_to_memory(const PackedLeanMap& map, const std::string& name) {
    const Ktx2FilePlan plan = plan_ktx2_file(name, map, true);
    std::vector<std::uint8_t> file(std::size_t(plan.size), 0);  // mip padding: zeros
    std::copy(plan.head.begin(), plan.head.end(), file.begin());
    for (std::size_t level = 0; level < map.levels.size(); ++level) {
        const PackedLevel& packed = map.levels[level];
        const auto lean1 = file.begin() + std::ptrdiff_t(plan.level_offsets[level]);
        const auto layer = std::ptrdiff_t(packed.lean1.size());
        std::copy(packed.lean1.begin(), packed.lean1.end(), lean1);
        std::copy(packed.lean2.begin(), packed.lean2.end(), lean1 + layer);
        if (map.has_plateau())
            std::copy(packed.plateau.begin(), packed.plateau.end(), lean1 + 2 * layer);
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
        for (int layer = 0; layer < (map.has_plateau() ? 3 : 2); ++layer) {
            const std::vector<std::uint8_t>& source =
                layer == 0 ? packed.lean1 : layer == 1 ? packed.lean2 : packed.plateau;
            std::uint8_t* destination = layer == 0   ? targets[level].lean1
                                        : layer == 1 ? targets[level].lean2
                                                     : targets[level].plateau;
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
