// A KTX2 file described for people (leanfade info).
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

#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/io/detail/atomic_file.hpp"

namespace leanfade::io {

using namespace ktx2_detail;

std::string describe(const Ktx2Info& info) {
    std::ostringstream out;
    out << "file: " << info.path << " (" << info.file_size << " bytes, KTX 2.0)\n";
    out << "vkFormat: " << info.vk_format << " (" << vk_format_name(info.vk_format)
        << "), typeSize " << info.type_size << "\n";
    out << "size: " << info.pixel_width << " x " << info.pixel_height << ", pixelDepth "
        << info.pixel_depth << ", layerCount " << info.layer_count << ", faceCount "
        << info.face_count << ", levelCount " << info.level_count << ", supercompressionScheme "
        << info.supercompression_scheme << " (" << supercompression_name(info.supercompression_scheme)
        << ")\n";
    out << "index: dfd " << info.dfd_byte_offset << " +" << info.dfd_byte_length << ", kvd "
        << info.kvd_byte_offset << " +" << info.kvd_byte_length << ", sgd " << info.sgd_byte_offset
        << " +" << info.sgd_byte_length << "\n";
    const Ktx2DataFormat& dfd = info.data_format;
    out << "data format: model " << dfd.color_model
        << (dfd.color_model == kDfdModelRgbsda ? " (RGBSDA)" : "") << ", primaries "
        << dfd.color_primaries << (dfd.color_primaries == kDfdPrimariesBt709 ? " (BT709)" : "")
        << ", transfer " << dfd.transfer_function
        << (dfd.transfer_function == kDfdTransferLinear ? " (linear)"
            : dfd.transfer_function == 2                ? " (sRGB)"
                                                        : "")
        << ", flags " << dfd.flags << ", bytesPlane0 " << dfd.bytes_plane[0] << ", "
        << dfd.samples.size() << " samples\n";
    for (std::size_t i = 0; i < dfd.samples.size(); ++i) {
        const Ktx2Sample& sample = dfd.samples[i];
        // RGBSDA channel ids: 0 red, 1 green, 2 blue, 13 stencil, 14 depth, 15 alpha.
        static constexpr const char* kChannelNames[16] = {
            "R", "G", "B", "3", "4", "5", "6", "7", "8", "9", "10", "11", "12", "S", "D", "A"};
        char bounds[64];
        std::snprintf(bounds, sizeof bounds, "lower 0x%08X, upper 0x%08X", sample.sample_lower,
                      sample.sample_upper);
        out << "  sample " << i << ": channel " << kChannelNames[sample.channel_id & 0xF]
            << ", bits " << sample.bit_offset << ".." << sample.bit_offset + sample.bit_length - 1
            << (sample.qualifiers & kDfdQualifierFloat ? ", float" : "")
            << (sample.qualifiers & kDfdQualifierSigned ? ", signed" : "") << ", " << bounds
            << "\n";
    }
    for (std::size_t level = 0; level < info.levels.size(); ++level) {
        const Ktx2Level& entry = info.levels[level];
        out << "level " << level << ": " << entry.width << " x " << entry.height << ", offset "
            << entry.byte_offset << ", length " << entry.byte_length << " (uncompressed "
            << entry.uncompressed_byte_length << ")\n";
    }
    out << "key/values (" << info.key_values.size() << "):\n";
    for (const auto& [key, value] : info.key_values) {
        // Cut as every file text is (docs/robustness.md): a key or value of 120 000 bytes was
        // printed whole, as one line.
        out << "  " << escape_text(key, kDescribedTextBytes) << " = "
            << escape_text(value, kDescribedTextBytes) << "\n";
    }
    return out.str();
}

}  // namespace leanfade::io
