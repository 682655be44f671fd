#include <algorithm>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <string>

#include "io_test_helpers.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::io {
namespace {

using test::expect_error;
using test::read_bytes;
using test::scratch_folder;
using test::store_u32_le;
using test::store_u64_le;
using test::u32_le;
using test::u64_le;
using test::write_bytes;

constexpr std::uint8_t kIdentifier[12] = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                          '0',  0xBB, '\r', '\n', 0x1A, '\n'};

// Header field offsets (KTX 2.0 §3).
constexpr std::size_t kVkFormat = 12, kTypeSize = 16, kPixelWidth = 20, kPixelHeight = 24,
                      kPixelDepth = 28, kLayerCount = 32, kFaceCount = 36, kLevelCount = 40,
                      kSupercompression = 44, kDfdOffset = 48, kDfdLength = 52, kKvdOffset = 56,
                      kKvdLength = 60, kSgdOffset = 64, kSgdLength = 72, kLevelIndex = 80;

struct StorageCase {
    Storage storage;
    std::uint32_t vk_format;
    std::uint32_t type_size;
    std::uint32_t texel_bytes;
};

constexpr StorageCase kStorages[] = {
    {Storage::Unorm8, 37, 1, 4},
    {Storage::Unorm16, 91, 2, 8},
    {Storage::Float16, 97, 2, 8},
    {Storage::Float32, 109, 4, 16},
};

int chain_length(int width, int height) {
    int levels = 1;
    for (int size = std::max(width, height); size > 1; size /= 2) ++levels;
    return levels;
}

// A packed map of arbitrary bytes (no dependency on the core packer).
PackedLeanMap make_map(Storage storage, int width, int height, int level_count, unsigned seed = 1) {
    const int texel_bytes = bytes_per_texel(storage);
    std::mt19937 random(seed);
    PackedLeanMap map;
    map.storage = storage;
    map.scale = 0.123456789f;
    map.roughness_baked = true;
    map.baked_shininess = 13777.0f;
    map.source_convention = NormalConvention::DirectX;
    map.generator = "leanfade test";
    for (int level = 0; level < level_count; ++level) {
        PackedLevel packed;
        packed.width = std::max(1, width >> level);
        packed.height = std::max(1, height >> level);
        const std::size_t size = std::size_t(packed.width * packed.height * texel_bytes);
        for (std::size_t i = 0; i < size; ++i) packed.lean1.push_back(std::uint8_t(random()));
        for (std::size_t i = 0; i < size; ++i) packed.lean2.push_back(std::uint8_t(random()));
        if (storage == Storage::Float16 || storage == Storage::Float32) {
            // Finite values only (read_ktx2 refuses NaN and infinity): the exponent's lowest bit
            // cleared where all its bits are set (the high byte of each little-endian value).
            const std::size_t type_size = storage == Storage::Float16 ? 2 : 4;
            for (std::vector<std::uint8_t>* layer : {&packed.lean1, &packed.lean2}) {
                for (std::size_t at = 0; at < layer->size(); at += type_size) {
                    std::uint8_t* value = layer->data() + at;
                    if (type_size == 2 && (value[1] & 0x7C) == 0x7C) value[1] &= 0xFB;
                    if (type_size == 4 && (value[3] & 0x7F) == 0x7F && (value[2] & 0x80) != 0)
                        value[2] &= 0x7F;
                }
            }
        }
        map.levels.push_back(std::move(packed));
    }
    return map;
}

void expect_same_map(const PackedLeanMap& actual, const PackedLeanMap& expected) {
    EXPECT_EQ(actual.storage, expected.storage);
    EXPECT_EQ(actual.encoding, expected.encoding);
    EXPECT_EQ(std::memcmp(&actual.scale, &expected.scale, sizeof(float)), 0)
        << actual.scale << " vs " << expected.scale;
    EXPECT_EQ(actual.roughness_baked, expected.roughness_baked);
    EXPECT_EQ(actual.baked_shininess, expected.baked_shininess);
    EXPECT_EQ(actual.source_convention, expected.source_convention);
    EXPECT_EQ(actual.generator, expected.generator);
    ASSERT_EQ(actual.levels.size(), expected.levels.size());
    for (std::size_t i = 0; i < expected.levels.size(); ++i) {
        EXPECT_EQ(actual.levels[i].width, expected.levels[i].width) << "level " << i;
        EXPECT_EQ(actual.levels[i].height, expected.levels[i].height) << "level " << i;
        EXPECT_TRUE(actual.levels[i].lean1 == expected.levels[i].lean1) << "level " << i;
        EXPECT_TRUE(actual.levels[i].lean2 == expected.levels[i].lean2) << "level " << i;
    }
}

// Raw key/value entries of a file, in file order, with padding checked.
std::vector<std::pair<std::string, std::string>> raw_key_values(
    const std::vector<std::uint8_t>& bytes) {
    const std::size_t offset = u32_le(bytes, kKvdOffset);
    const std::size_t length = u32_le(bytes, kKvdLength);
    std::vector<std::pair<std::string, std::string>> entries;
    std::size_t position = offset;
    while (position < offset + length) {
        const std::uint32_t entry_length = u32_le(bytes, position);
        const std::string entry(bytes.begin() + std::ptrdiff_t(position + 4),
                                bytes.begin() + std::ptrdiff_t(position + 4 + entry_length));
        const std::size_t nul = entry.find('\0');
        EXPECT_NE(nul, std::string::npos);
        entries.emplace_back(entry.substr(0, nul), entry.substr(nul + 1));
        position += 4 + entry_length;
        while (position % 4 != 0) {
            EXPECT_EQ(bytes[position], 0) << "padding";
            ++position;
        }
    }
    EXPECT_EQ(position, offset + length);
    return entries;
}

std::size_t find_text(const std::vector<std::uint8_t>& bytes, const std::string& text) {
    const auto found = std::search(bytes.begin(), bytes.end(), text.begin(), text.end());
    EXPECT_NE(found, bytes.end()) << text;
    return std::size_t(found - bytes.begin());
}

// Writes `bytes` after applying `patch`, then expects read_ktx2 to fail with `cause`.
template <class Patch>
void expect_rejected(const std::string& path, std::vector<std::uint8_t> bytes, Patch&& patch,
                     const std::string& cause) {
    patch(bytes);
    write_bytes(path, bytes);
    expect_error([&] { read_ktx2(path); }, path, cause);
}

TEST(Ktx2, RoundTripIsBitExactForAllStorages) {
    const std::string folder = scratch_folder();
    const int sizes[][2] = {{37, 20}, {1, 1}, {64, 1}, {3, 50}};
    for (const StorageCase& storage : kStorages) {
        for (const auto& size : sizes) {
            const int levels = chain_length(size[0], size[1]);
            SCOPED_TRACE(std::string(to_string(storage.storage)) + " " + std::to_string(size[0]) +
                         "x" + std::to_string(size[1]) + " levels " + std::to_string(levels));
            const PackedLeanMap map = make_map(storage.storage, size[0], size[1], levels,
                                               unsigned(size[0] * 7 + size[1]));
            const std::string path = folder + "/map.ktx2";
            write_ktx2(path, map);
            expect_same_map(read_ktx2(path), map);
        }
    }
}

// Ktx2Writer (what `leanfade bake` fills straight from the bake): the file appears only on
// commit, and filling its targets gives write_ktx2's bytes.
TEST(Ktx2, WriterInPlaceEqualsWriteKtx2AndAppearsOnlyOnCommit) {
    const std::string folder = scratch_folder();
    for (const StorageCase& storage : kStorages) {
        SCOPED_TRACE(to_string(storage.storage));
        const PackedLeanMap map = make_map(storage.storage, 37, 20, chain_length(37, 20), 11);
        write_ktx2(folder + "/whole.ktx2", map);
        PackedLeanMap layout = map;
        for (PackedLevel& level : layout.levels) {
            level.lean1.clear();
            level.lean2.clear();
        }
        const std::string path = folder + "/in_place.ktx2";
        {
            Ktx2Writer abandoned(path, layout);
            ASSERT_EQ(abandoned.targets().size(), map.levels.size());
        }
        EXPECT_FALSE(std::filesystem::exists(path));
        EXPECT_EQ(test::folder_entries(folder), std::vector<std::string>{"whole.ktx2"});
        Ktx2Writer writer(path, layout);
        ASSERT_EQ(writer.targets().size(), map.levels.size());
        for (std::size_t l = 0; l < map.levels.size(); ++l) {
            std::copy(map.levels[l].lean1.begin(), map.levels[l].lean1.end(),
                      writer.targets()[l].lean1);
            std::copy(map.levels[l].lean2.begin(), map.levels[l].lean2.end(),
                      writer.targets()[l].lean2);
        }
        EXPECT_FALSE(std::filesystem::exists(path));
        writer.commit();
        EXPECT_EQ(read_bytes(path), read_bytes(folder + "/whole.ktx2"));
        std::filesystem::remove(path);
    }
    // A layout is checked as a map is (but without layer bytes).
    PackedLeanMap bad = make_map(Storage::Unorm16, 8, 8, 4, 1);
    bad.scale = -1.0f;
    expect_error([&] { Ktx2Writer writer(folder + "/bad.ktx2", bad); }, folder + "/bad.ktx2",
                 "is not finite and > 0");
    EXPECT_FALSE(std::filesystem::exists(folder + "/bad.ktx2"));
}

TEST(Ktx2, MetadataRoundTripsExactly) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/map.ktx2";
    std::mt19937 random(11);
    std::vector<float> scales = {1.0f,
                                 0.1f,
                                 3.14159274f,
                                 1e-7f,
                                 123456.789f,
                                 std::numeric_limits<float>::denorm_min(),
                                 std::numeric_limits<float>::max()};
    for (int i = 0; i < 50; ++i) {
        const std::uint32_t bits = (random() & 0x7FFFFFFFu) % 0x7F800000u;  // positive finite
        float value;
        std::memcpy(&value, &bits, 4);
        if (value > 0.0f) scales.push_back(value);
    }
    for (const float scale : scales) {
        PackedLeanMap map = make_map(Storage::Unorm16, 5, 3, 3);
        map.scale = std::min(scale, kMaxLeanScale);  // read_ktx2 refuses a larger sc
        map.baked_shininess = scale;
        map.roughness_baked = false;
        map.source_convention = NormalConvention::OpenGL;
        write_ktx2(path, map);
        expect_same_map(read_ktx2(path), map);
    }
    PackedLeanMap unnamed = make_map(Storage::Unorm8, 2, 2, 2);
    unnamed.generator.clear();
    write_ktx2(path, unnamed);
    EXPECT_THAT(read_ktx2(path).generator, ::testing::StartsWith("leanfade "));
}

TEST(Ktx2, HeaderIndexAndLevelsFollowTheSpec) {
    const std::string folder = scratch_folder();
    for (const StorageCase& storage : kStorages) {
        SCOPED_TRACE(to_string(storage.storage));
        const int width = 37, height = 20, levels = chain_length(width, height);
        ASSERT_EQ(levels, 6);
        const PackedLeanMap map = make_map(storage.storage, width, height, levels);
        const std::string path = folder + "/map.ktx2";
        write_ktx2(path, map);
        const std::vector<std::uint8_t> bytes = read_bytes(path);

        EXPECT_EQ(std::memcmp(bytes.data(), kIdentifier, 12), 0);
        EXPECT_EQ(u32_le(bytes, kVkFormat), storage.vk_format);
        EXPECT_EQ(u32_le(bytes, kTypeSize), storage.type_size);
        EXPECT_EQ(u32_le(bytes, kPixelWidth), 37u);
        EXPECT_EQ(u32_le(bytes, kPixelHeight), 20u);
        EXPECT_EQ(u32_le(bytes, kPixelDepth), 0u);
        EXPECT_EQ(u32_le(bytes, kLayerCount), 2u);
        EXPECT_EQ(u32_le(bytes, kFaceCount), 1u);
        EXPECT_EQ(u32_le(bytes, kLevelCount), 6u);
        EXPECT_EQ(u32_le(bytes, kSupercompression), 0u);
        const std::uint32_t dfd_offset = u32_le(bytes, kDfdOffset);
        const std::uint32_t dfd_length = u32_le(bytes, kDfdLength);
        const std::uint32_t kvd_offset = u32_le(bytes, kKvdOffset);
        const std::uint32_t kvd_length = u32_le(bytes, kKvdLength);
        EXPECT_EQ(dfd_offset, kLevelIndex + 24 * 6);  // right after the level index
        EXPECT_EQ(dfd_length, 4u + 24u + 4u * 16u);
        EXPECT_EQ(kvd_offset, dfd_offset + dfd_length);
        EXPECT_EQ(kvd_offset % 4, 0u);
        EXPECT_EQ(kvd_length % 4, 0u);
        EXPECT_EQ(u64_le(bytes, kSgdOffset), 0u);
        EXPECT_EQ(u64_le(bytes, kSgdLength), 0u);

        const std::uint64_t alignment = std::lcm(std::uint64_t(storage.texel_bytes), 4u);
        std::uint64_t previous_offset = 0;
        for (int level = levels - 1; level >= 0; --level) {  // smallest level first in the file
            const std::size_t entry = kLevelIndex + 24 * std::size_t(level);
            const std::uint64_t offset = u64_le(bytes, entry);
            const std::uint64_t length = u64_le(bytes, entry + 8);
            const PackedLevel& packed = map.levels[std::size_t(level)];
            EXPECT_EQ(length, std::uint64_t(packed.width) * std::uint64_t(packed.height) *
                                  storage.texel_bytes * 2)
                << "level " << level;
            EXPECT_EQ(u64_le(bytes, entry + 16), length) << "uncompressedByteLength";
            EXPECT_EQ(offset % alignment, 0u) << "level " << level;
            if (level == levels - 1) {
                EXPECT_GE(offset, std::uint64_t(kvd_offset) + kvd_length);
                EXPECT_LT(offset - (kvd_offset + kvd_length), alignment);  // padding only
            } else {
                EXPECT_GT(offset, previous_offset) << "levels stored smallest first";
            }
            previous_offset = offset;
            // Layer 0 (lean1) then layer 1 (lean2), back to back.
            EXPECT_EQ(std::memcmp(bytes.data() + offset, packed.lean1.data(), packed.lean1.size()),
                      0);
            EXPECT_EQ(std::memcmp(bytes.data() + offset + packed.lean1.size(), packed.lean2.data(),
                                  packed.lean2.size()),
                      0);
            if (level == 0) {
                EXPECT_EQ(offset + length, bytes.size()) << "level 0 ends the file";
            }
        }
    }
}

TEST(Ktx2, DataFormatDescriptorFollowsTheSpec) {
    const std::string folder = scratch_folder();
    for (const StorageCase& storage : kStorages) {
        SCOPED_TRACE(to_string(storage.storage));
        const std::string path = folder + "/map.ktx2";
        write_ktx2(path, make_map(storage.storage, 4, 4, 3));
        const std::vector<std::uint8_t> bytes = read_bytes(path);
        const std::size_t dfd = u32_le(bytes, kDfdOffset);
        EXPECT_EQ(u32_le(bytes, dfd), 92u);                       // dfdTotalSize
        EXPECT_EQ(u32_le(bytes, dfd + 4), 0u);                    // vendor KHR, type basic
        EXPECT_EQ(u32_le(bytes, dfd + 8), 2u | (88u << 16));      // version 1.3, block size 88
        EXPECT_EQ(bytes[dfd + 12], 1);                            // model RGBSDA
        EXPECT_EQ(bytes[dfd + 13], 1);                            // primaries BT709
        EXPECT_EQ(bytes[dfd + 14], 1);                            // transfer LINEAR
        EXPECT_EQ(bytes[dfd + 15], 0);                            // flags: straight alpha
        EXPECT_EQ(u32_le(bytes, dfd + 16), 0u);                   // texel block 1x1x1x1
        EXPECT_EQ(u32_le(bytes, dfd + 20), storage.texel_bytes);  // bytesPlane0
        EXPECT_EQ(u32_le(bytes, dfd + 24), 0u);
        const bool is_float = storage.vk_format == 97 || storage.vk_format == 109;
        const std::uint32_t bits = storage.type_size * 8;
        const std::uint8_t channel_ids[4] = {0, 1, 2, 15};
        for (std::uint32_t c = 0; c < 4; ++c) {
            const std::size_t sample = dfd + 28 + 16 * c;
            EXPECT_EQ(u32_le(bytes, sample) & 0xFFFF, c * bits) << "bitOffset";
            EXPECT_EQ(bytes[sample + 2], bits - 1) << "bitLength";
            EXPECT_EQ(bytes[sample + 3], channel_ids[c] | (is_float ? 0xC0 : 0x00))
                << "channelType + qualifiers";
            EXPECT_EQ(u32_le(bytes, sample + 4), 0u) << "samplePosition";
            EXPECT_EQ(u32_le(bytes, sample + 8), is_float ? 0xBF800000u : 0u) << "sampleLower";
            EXPECT_EQ(u32_le(bytes, sample + 12),
                      is_float ? 0x3F800000u : (bits == 8 ? 255u : 65535u))
                << "sampleUpper";
        }
    }
}

TEST(Ktx2, KeyValueDataIsSortedPaddedAndComplete) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/map.ktx2";
    PackedLeanMap map = make_map(Storage::Float16, 6, 6, 3);
    map.scale = 0.1f;
    write_ktx2(path, map);
    const auto entries = raw_key_values(read_bytes(path));
    std::vector<std::string> keys;
    for (const auto& entry : entries) keys.push_back(entry.first);
    EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end()));
    using Entry = std::pair<std::string, std::string>;
    EXPECT_EQ(entries, (std::vector<Entry>{
                           {"KTXorientation", std::string("rd\0", 3)},
                           {"KTXwriter", std::string("leanfade test\0", 14)},
                           {"LEANFADEbakedShininess", std::string("13777\0", 6)},
                           {"LEANFADElayout", std::string("lean1,lean2 v1\0", 15)},
                           {"LEANFADEnormalConvention", std::string("directx\0", 8)},
                           {"LEANFADEroughnessBaked", std::string("1\0", 2)},
                           {"LEANFADEscale", std::string("0.1\0", 4)},
                       }));
}

TEST(Ktx2, InspectAndDescribe) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/map.ktx2";
    write_ktx2(path, make_map(Storage::Unorm16, 37, 20, 6));
    const Ktx2Info info = inspect_ktx2(path);
    EXPECT_EQ(info.vk_format, 91u);
    EXPECT_EQ(info.pixel_width, 37u);
    EXPECT_EQ(info.layer_count, 2u);
    ASSERT_EQ(info.levels.size(), 6u);
    EXPECT_EQ(info.levels[5].width, 1u);
    EXPECT_EQ(info.levels[2].width, 9u);
    EXPECT_EQ(info.levels[2].height, 5u);
    EXPECT_EQ(info.levels[2].byte_length, 9u * 5u * 8u * 2u);
    EXPECT_EQ(info.data_format.samples.size(), 4u);
    ASSERT_NE(info.find("LEANFADEscale"), nullptr);
    EXPECT_EQ(*info.find("LEANFADEscale"), "0.12345679");
    EXPECT_EQ(info.find("nothing"), nullptr);

    const std::string text = describe(info);
    EXPECT_THAT(text, ::testing::HasSubstr("VK_FORMAT_R16G16B16A16_UNORM"));
    EXPECT_THAT(text, ::testing::HasSubstr("37 x 20"));
    EXPECT_THAT(text, ::testing::HasSubstr("layerCount 2"));
    EXPECT_THAT(text, ::testing::HasSubstr("level 2: 9 x 5, offset "));
    EXPECT_THAT(text, ::testing::HasSubstr("KTXorientation = rd\n"));
    EXPECT_THAT(text, ::testing::HasSubstr("LEANFADElayout = lean1,lean2 v1\n"));
    EXPECT_THAT(text, ::testing::HasSubstr("transfer 1 (linear)"));
    EXPECT_EQ(text.back(), '\n');
}

TEST(Ktx2, InspectDescribesForeignFilesThatReadRefuses) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/cube.ktx2";
    write_ktx2(path, make_map(Storage::Unorm8, 4, 4, 3));
    std::vector<std::uint8_t> bytes = read_bytes(path);
    store_u32_le(bytes, kLayerCount, 0);
    store_u32_le(bytes, kVkFormat, 43);  // VK_FORMAT_R8G8B8A8_SRGB
    write_bytes(path, bytes);
    EXPECT_NO_THROW(inspect_ktx2(path));
    EXPECT_THAT(describe(inspect_ktx2(path)),
                ::testing::HasSubstr("vkFormat: 43 (VK_FORMAT_R8G8B8A8_SRGB)"));
    expect_error([&] { read_ktx2(path); }, path, "unsupported vkFormat 43");
}

TEST(Ktx2, MissingEmptyTruncatedAndGarbageFilesThrow) {
    const std::string folder = scratch_folder();
    const std::string good = folder + "/good.ktx2";
    write_ktx2(good, make_map(Storage::Unorm16, 37, 20, 6));
    const std::vector<std::uint8_t> bytes = read_bytes(good);

    const std::string missing = folder + "/missing.ktx2";
    expect_error([&] { read_ktx2(missing); }, missing, "cannot open (No such file or directory)");
    expect_error([&] { inspect_ktx2(missing); }, missing, "cannot open");
    const std::string empty = folder + "/empty.ktx2";
    write_bytes(empty, {});
    expect_error([&] { read_ktx2(empty); }, empty, "empty file");

    const std::string path = folder + "/bad.ktx2";
    const std::size_t dfd = u32_le(bytes, kDfdOffset);
    const std::size_t kvd = u32_le(bytes, kKvdOffset);
    const std::pair<std::size_t, std::string> cuts[] = {
        {5, "truncated KTX2 identifier"},
        {12, "truncated KTX2 header"},
        {79, "truncated KTX2 header"},
        {100, "truncated KTX2 level index"},
        {dfd + 10, "runs past the end of the file"},
        {kvd + 20, "runs past the end of the file"},
        {bytes.size() / 2, "runs past the end of the file"},
        {bytes.size() - 1, "level 0 data (offset"},
    };
    for (const auto& [length, cause] : cuts) {
        SCOPED_TRACE("truncated to " + std::to_string(length));
        write_bytes(
            path, std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + std::ptrdiff_t(length)));
        expect_error([&] { read_ktx2(path); }, path, cause);
    }

    std::vector<std::uint8_t> garbage(500);
    std::mt19937 random(5);
    for (auto& byte : garbage) byte = std::uint8_t(random());
    write_bytes(path, garbage);
    expect_error([&] { read_ktx2(path); }, path, "not a KTX 2.0 file (bad identifier)");
    std::copy(std::begin(kIdentifier), std::end(kIdentifier), garbage.begin());
    write_bytes(path, garbage);
    expect_error([&] { read_ktx2(path); }, path, "");  // any cause, but a leanfade::Error
}

TEST(Ktx2, HostileHeadersAreRefusedBeforeAllocating) {
    const std::string folder = scratch_folder();
    const std::string good = folder + "/good.ktx2";
    write_ktx2(good, make_map(Storage::Float32, 37, 20, 6));
    const std::vector<std::uint8_t> bytes = read_bytes(good);
    const std::string path = folder + "/bad.ktx2";

    test::reset_largest_allocation();
    expect_rejected(
        path, bytes,
        [](auto& b) {
            store_u32_le(b, kPixelWidth, 100000);
            store_u32_le(b, kPixelHeight, 100000);
        },
        "image size 100000x100000 exceeds the limit of 16384 texels per side");
    EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);

    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kPixelWidth, 0); },
        "image width or height is 0");
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kLayerCount, 1); },
        "layerCount 1 (a LEAN map has 2 layers");
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kLayerCount, 0); }, "layerCount 0");
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kFaceCount, 6); }, "faceCount 6");
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kPixelDepth, 3); }, "pixelDepth 3");
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kSupercompression, 3); },
        "supercompressionScheme 3 (ZLIB) is not supported");
    // Zstandard's level data is unsized: a plain file that says scheme 2 keeps bytesPlane0.
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kSupercompression, 2); },
        "bytesPlane0 16, expected 0 for supercompressed data");
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kTypeSize, 1); },
        "typeSize 1 does not match VK_FORMAT_R32G32B32A32_SFLOAT");
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kVkFormat, 109 + 1); },
        "unsupported vkFormat 110");
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kLevelCount, 7); },
        "levelCount 7 exceeds the 6 levels of a 37x20 MIP chain");
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kLevelCount, 0xFFFFFFFFu); },
        "levelCount 4294967295 exceeds");
    expect_rejected(
        path, bytes, [](auto& b) { store_u32_le(b, kLevelCount, 0); }, "levelCount 0");
    // The same absurd level counts seen by inspect (no chain check there).
    std::vector<std::uint8_t> many_levels = bytes;
    store_u32_le(many_levels, kLevelCount, 1000000);
    write_bytes(path, many_levels);
    expect_error([&] { inspect_ktx2(path); }, path, "levelCount 1000000 is more than 32");
}

TEST(Ktx2, OffsetsAndLengthsOutsideTheFileAreRefused) {
    const std::string folder = scratch_folder();
    const std::string good = folder + "/good.ktx2";
    write_ktx2(good, make_map(Storage::Unorm8, 37, 20, 6));
    const std::vector<std::uint8_t> bytes = read_bytes(good);
    const std::string path = folder + "/bad.ktx2";
    const std::uint64_t max64 = std::numeric_limits<std::uint64_t>::max();

    test::reset_largest_allocation();
    expect_rejected(
        path, bytes, [&](auto& b) { store_u64_le(b, kLevelIndex, max64 - 10); },
        "level 0 data (offset 18446744073709551605, length 5920) runs past the end");
    expect_rejected(
        path, bytes, [&](auto& b) { store_u64_le(b, kLevelIndex + 24 + 8, max64); },
        "level 1 data");
    expect_rejected(
        path, bytes, [&](auto& b) { store_u64_le(b, kLevelIndex, b.size()); }, "level 0 data");
    expect_rejected(
        path, bytes, [&](auto& b) { store_u32_le(b, kDfdLength, 0xFFFFFFF0u); },
        "data format descriptor runs past the end of the file");
    expect_rejected(
        path, bytes, [&](auto& b) { store_u32_le(b, kKvdOffset, 0xFFFFFFFFu); },
        "key/value data runs past the end of the file");
    expect_rejected(
        path, bytes, [&](auto& b) { store_u64_le(b, kSgdOffset, max64); },
        "supercompression global data runs past the end of the file");
    EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);

    // Inside the file but wrong.
    expect_rejected(
        path, bytes, [&](auto& b) { store_u64_le(b, kLevelIndex + 8, 5920 - 4); },
        "level 0 byteLength 5916");
    expect_rejected(
        path, bytes, [&](auto& b) { store_u64_le(b, kLevelIndex, u64_le(b, kLevelIndex) - 2); },
        "level 0 data (offset 2430, length 5920) overlaps level 1 data (offset 992, length 1440)");
    expect_rejected(
        path, bytes,
        [&](auto& b) {
            b.insert(b.end(), {0, 0});  // level 0 ends the file: 2 bytes more, then 2 bytes later
            store_u64_le(b, kLevelIndex, u64_le(b, kLevelIndex) + 2);
        },
        "is not aligned to 4 bytes");
    expect_rejected(
        path, bytes,
        [&](auto& b) {
            const std::size_t kvd = u32_le(b, kKvdOffset);
            store_u32_le(b, kvd, 0x10000);
        },
        "runs past the key/value data");
}

TEST(Ktx2, InconsistentDescriptorsAndKeysAreRefused) {
    const std::string folder = scratch_folder();
    const std::string good = folder + "/good.ktx2";
    PackedLeanMap map = make_map(Storage::Unorm16, 9, 7, 4);
    map.scale = 0.5f;
    write_ktx2(good, map);
    const std::vector<std::uint8_t> bytes = read_bytes(good);
    const std::string path = folder + "/bad.ktx2";
    const std::size_t dfd = u32_le(bytes, kDfdOffset);

    expect_rejected(
        path, bytes, [&](auto& b) { b[dfd + 14] = 2; }, "transfer is not LINEAR");
    expect_rejected(
        path, bytes, [&](auto& b) { b[dfd + 12] = 2; }, "not RGBSDA");
    expect_rejected(
        path, bytes, [&](auto& b) { b[dfd + 28 + 16 + 3] |= 0xC0; }, "(sample 1)");
    expect_rejected(
        path, bytes, [&](auto& b) { store_u32_le(b, dfd + 28 + 16 * 3 + 12, 255); }, "(sample 3)");
    expect_rejected(
        path, bytes, [&](auto& b) { store_u32_le(b, dfd, 91); },
        "dfdTotalSize 91 differs from dfdByteLength 92");

    const auto replace = [&](const std::string& from, const std::string& to) {
        return [&, from, to](std::vector<std::uint8_t>& b) {
            ASSERT_EQ(from.size(), to.size());
            std::copy(to.begin(), to.end(), b.begin() + std::ptrdiff_t(find_text(b, from)));
        };
    };
    expect_rejected(path, bytes, replace(std::string("lean1,lean2 v1"), "lean1,lean2 v3"),
                    "unsupported LEANFADElayout 'lean1,lean2 v3'");
    // Version 2 (the signed encoding) is for float vkFormats only.
    expect_rejected(path, bytes, replace(std::string("lean1,lean2 v1"), "lean1,lean2 v2"),
                    "LEANFADElayout 'lean1,lean2 v2' (signed values) needs a float vkFormat, not "
                    "VK_FORMAT_R16G16B16A16_UNORM");
    expect_rejected(
        path, bytes,
        replace(std::string("LEANFADEscale\0000.5", 17), std::string("LEANFADEscale\0nan", 17)),
        "bad LEANFADEscale value 'nan'");
    expect_rejected(
        path, bytes,
        replace(std::string("LEANFADEscale\0000.5", 17), std::string("LEANFADEscale\0000.0", 17)),
        "LEANFADEscale must be > 0");
    expect_rejected(path, bytes, replace("LEANFADEroughnessBaked", "LEANFADEroughnessBakeX"),
                    "missing key LEANFADEroughnessBaked");
    expect_rejected(path, bytes, replace("directx", "DirectX"),
                    "bad LEANFADEnormalConvention value 'DirectX'");
    expect_rejected(path, bytes, replace(std::string("rd\0", 3), std::string("ru\0", 3)),
                    "unsupported KTXorientation 'ru'");
    expect_rejected(path, bytes,
                    replace(std::string("Baked\0001", 7), std::string("Baked\0002", 7)),
                    "bad LEANFADEroughnessBaked value '2'");
}

// Float maps store signed values (layout version 2); version 1 float maps, as leanfade 0.1
// wrote them (the offset encoding), load as before and decode to the same moments.
TEST(Ktx2, SignedFloatMapsAreLayoutVersion2AndVersion1MapsLoadAsBefore) {
    const std::string folder = scratch_folder();
    LeanMap moments;
    moments.scale = 0.75f;
    MomentLevel level;
    level.width = level.height = 1;
    level.normal = {glm::vec3(0.2f, -0.1f, 0.97f)};
    level.mean = {glm::vec2(0.25f, -0.125f)};
    level.second = {glm::vec3(0.0625f + 1e-3f, 0.015625f + 2e-3f, -0.03125f + 1e-4f)};
    moments.levels = {level};
    for (const Storage storage : {Storage::Float16, Storage::Float32}) {
        SCOPED_TRACE(to_string(storage));
        const PackedLeanMap signed_map = pack_lean_map(moments, storage, "leanfade test");
        ASSERT_EQ(signed_map.encoding, LeanEncoding::Signed);
        const PackedLeanMap offset_map =
            pack_lean_map(moments, storage, LeanEncoding::Offset, "leanfade test");
        const std::string v2 = folder + "/v2.ktx2", v1 = folder + "/v1.ktx2";
        write_ktx2(v2, signed_map);
        write_ktx2(v1, offset_map);
        const auto layout = [](const std::string& path) {
            for (const auto& [key, value] : raw_key_values(read_bytes(path)))
                if (key == "LEANFADElayout") return value;
            return std::string();
        };
        EXPECT_EQ(layout(v2), std::string("lean1,lean2 v2\0", 15));
        EXPECT_EQ(layout(v1), std::string("lean1,lean2 v1\0", 15));
        const PackedLeanMap read_v2 = read_ktx2(v2), read_v1 = read_ktx2(v1);
        expect_same_map(read_v2, signed_map);
        expect_same_map(read_v1, offset_map);
        // Both decode to the moments, each within its storage's rounding: the signed one to
        // half's relative 2^-11, the offset one only to 2^-11 of the range (sc, sc^2).
        const MomentLevel a = unpack_lean_map(read_v2).levels[0];
        const MomentLevel b = unpack_lean_map(read_v1).levels[0];
        const float relative = storage == Storage::Float16 ? 4.9e-4f : 1.2e-7f;
        const float sc = moments.scale;
        for (int c = 0; c < 2; ++c) {
            EXPECT_NEAR(a.mean[0][c], level.mean[0][c], std::abs(level.mean[0][c]) * relative);
            EXPECT_NEAR(b.mean[0][c], level.mean[0][c], sc * 2.0f * relative);
        }
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(a.second[0][c], level.second[0][c],
                        std::abs(level.second[0][c]) * relative);
            EXPECT_NEAR(b.second[0][c], level.second[0][c], sc * sc * 2.0f * relative);
        }
    }
    // A signed map in a UNORM storage is refused by the packer and the writer.
    EXPECT_THROW(pack_lean_map(moments, Storage::Unorm16, LeanEncoding::Signed, "x"), Error);
    PackedLeanMap unorm = pack_lean_map(moments, Storage::Unorm16, "x");
    unorm.encoding = LeanEncoding::Signed;
    expect_error([&] { write_ktx2(folder + "/bad.ktx2", unorm); }, folder + "/bad.ktx2",
                 "the signed encoding needs a float storage, not 16");
}

TEST(Ktx2, WriteRefusesInconsistentMaps) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/map.ktx2";
    PackedLeanMap map = make_map(Storage::Unorm16, 8, 8, 4);
    map.levels.push_back(map.levels.back());
    expect_error([&] { write_ktx2(path, map); }, path,
                 "5 levels for a 8x8 map (a LEAN map has all 4 levels of its MIP chain)");
    map = make_map(Storage::Unorm16, 8, 8, 3);
    expect_error([&] { write_ktx2(path, map); }, path,
                 "3 levels for a 8x8 map (a LEAN map has all 4 levels of its MIP chain)");
    map = make_map(Storage::Unorm16, 8, 8, 4);
    map.levels[2].width = 3;
    expect_error([&] { write_ktx2(path, map); }, path, "level 2 is 3x2, expected 2x2");
    map = make_map(Storage::Unorm16, 8, 8, 4);
    map.levels[1].lean2.pop_back();
    expect_error([&] { write_ktx2(path, map); }, path,
                 "level 1: lean2 holds 127 bytes, expected 128");
    map = make_map(Storage::Unorm16, 8, 8, 4);
    map.scale = std::numeric_limits<float>::quiet_NaN();
    expect_error([&] { write_ktx2(path, map); }, path, "LEAN scale nan is not finite and > 0");
    map.scale = 0.0f;
    expect_error([&] { write_ktx2(path, map); }, path, "LEAN scale 0 is not finite and > 0");
    map.scale = 1.0f;
    map.baked_shininess = -1.0f;
    expect_error([&] { write_ktx2(path, map); }, path, "baked shininess -1");
    EXPECT_TRUE(test::folder_entries(folder).empty());
}

// Zstandard supercompression (KTX2 scheme 2): every level one frame, unaligned, bytesPlane0 0,
// and the same map read back bit for bit; the in-place writer and the in-memory writer give the
// same bytes as write_ktx2.
TEST(Ktx2, ZstandardRoundTripsBitExactForAllStorages) {
    const std::string folder = scratch_folder();
    WriteOptions zstd;
    zstd.supercompression = Supercompression::Zstandard;
    for (const StorageCase& storage : kStorages) {
        for (const auto& size : {std::pair{37, 20}, std::pair{1, 1}, std::pair{3, 50}}) {
            SCOPED_TRACE(std::string(to_string(storage.storage)) + " " +
                         std::to_string(size.first) + "x" + std::to_string(size.second));
            const int levels = chain_length(size.first, size.second);
            PackedLeanMap map = make_map(storage.storage, size.first, size.second, levels, 5);
            // Half of every layer constant: compressible, as real maps' flat ground is.
            for (PackedLevel& level : map.levels)
                for (std::vector<std::uint8_t>* layer : {&level.lean1, &level.lean2})
                    std::fill(layer->begin(), layer->begin() + std::ptrdiff_t(layer->size() / 2), 0);
            const std::string path = folder + "/zstd.ktx2";
            write_ktx2(path, map, zstd);
            expect_same_map(read_ktx2(path), map);
            const std::vector<std::uint8_t> bytes = read_bytes(path);
            EXPECT_EQ(u32_le(bytes, kSupercompression), 2u);
            EXPECT_EQ(u64_le(bytes, kSgdLength), 0u);
            const Ktx2Info info = inspect_ktx2(path);
            EXPECT_EQ(info.data_format.bytes_plane[0], 0u);
            for (std::size_t l = 0; l < info.levels.size(); ++l)
                EXPECT_EQ(info.levels[l].uncompressed_byte_length,
                          2 * map.levels[l].lean1.size());
            if (size.first == 37) {
                write_ktx2(folder + "/plain.ktx2", map);
                EXPECT_LT(bytes.size(), read_bytes(folder + "/plain.ktx2").size() * 3 / 4);
            }
            EXPECT_EQ(write_ktx2_to_memory(map, "m", zstd), bytes);
            expect_same_map(read_ktx2_from_memory(bytes, "m"), map);
        }
    }
    WriteOptions bad = zstd;
    bad.zstd_level = 23;
    expect_error([&] { write_ktx2(folder + "/bad.ktx2", make_map(Storage::Unorm8, 4, 4, 3), bad); },
                 folder + "/bad.ktx2", "Zstandard level 23 is not in 1..");
}

TEST(Ktx2, ZstandardWriterDropsAnEmptyPlateauLayerBeforeCommit) {
    const std::string folder = scratch_folder();
    WriteOptions zstd;
    zstd.supercompression = Supercompression::Zstandard;
    PackedLeanMap map = make_map(Storage::Unorm16, 37, 20, chain_length(37, 20), 3);
    PackedLeanMap layout = map;
    layout.plateau_epsilon = 0.01f;
    for (PackedLevel& level : layout.levels) level = {level.width, level.height, {}, {}, {}};
    const std::string path = folder + "/dropped.ktx2";
    Ktx2Writer writer(path, layout, zstd);
    for (std::size_t l = 0; l < map.levels.size(); ++l) {
        ASSERT_NE(writer.targets()[l].plateau, nullptr);
        std::copy(map.levels[l].lean1.begin(), map.levels[l].lean1.end(), writer.targets()[l].lean1);
        std::copy(map.levels[l].lean2.begin(), map.levels[l].lean2.end(), writer.targets()[l].lean2);
    }
    EXPECT_TRUE(writer.drop_plateau_layer());
    EXPECT_FALSE(writer.drop_plateau_layer());
    writer.commit();
    write_ktx2(folder + "/two_layers.ktx2", map, zstd);
    EXPECT_EQ(read_bytes(path), read_bytes(folder + "/two_layers.ktx2"));
    EXPECT_FALSE(read_ktx2(path).has_plateau());
    // An uncompressed file's size is fixed: nothing is dropped.
    Ktx2Writer plain(folder + "/plain.ktx2", layout);
    EXPECT_FALSE(plain.drop_plateau_layer());
}

TEST(Ktx2, CorruptZstandardLevelsAreRefusedNamingTheLevel) {
    const std::string folder = scratch_folder();
    WriteOptions zstd;
    zstd.supercompression = Supercompression::Zstandard;
    const std::string good = folder + "/good.ktx2";
    write_ktx2(good, make_map(Storage::Float16, 37, 20, 6), zstd);
    const std::vector<std::uint8_t> bytes = read_bytes(good);
    const std::size_t level0 = kLevelIndex;  // level 0's index entry
    const std::uint64_t offset = u64_le(bytes, level0), length = u64_le(bytes, level0 + 8);
    const std::string path = folder + "/bad.ktx2";
    // A flipped byte in the middle of the frame: the checksum (or the decoder) catches it.
    expect_rejected(
        path, bytes, [&](auto& b) { b[std::size_t(offset + length / 2)] ^= 0x5A; },
        "level 0: corrupt Zstandard data");
    expect_rejected(
        path, bytes, [&](auto& b) { store_u64_le(b, level0 + 8, length - 3); },
        "level 0: its Zstandard frame is truncated");
    expect_rejected(
        path, bytes, [&](auto& b) { store_u64_le(b, level0 + 16, 37 * 20 * 8 * 2 + 8); },
        "level 0 byteLength");
    expect_rejected(
        path, bytes, [&](auto& b) { b[std::size_t(offset)] ^= 0xFF; },
        "level 0: not Zstandard data");
    expect_rejected(
        path, bytes,
        [&](auto& b) {
            b.insert(b.end(), {1, 2, 3, 4});
            store_u64_le(b, level0 + 8, length + 4);
        },
        "level 0: 4 bytes after its Zstandard frame");
    // Levels 0 and 1 swapped: level 0's frame is longer than any frame of level 1's size.
    expect_rejected(
        path, bytes,
        [&](auto& b) {
            const std::uint64_t offset1 = u64_le(b, level0 + 24), length1 = u64_le(b, level0 + 32);
            store_u64_le(b, level0 + 24, offset);
            store_u64_le(b, level0 + 32, length);
            store_u64_le(b, level0, offset1);
            store_u64_le(b, level0 + 8, length1);
        },
        "level 1 byteLength 11854 / uncompressed 2880, expected a Zstandard frame / 2880");
}

}  // namespace
}  // namespace leanfade::io
