// Image formats read through OpenImageIO: JPEG, TGA, DDS (BC1-BC5), TIFF, PSD, BMP, Radiance HDR,
// WebP, and OpenEXR files of the compressions tinyexr cannot decode (formats.hpp).
//
// Each file goes to the one reader of the format its content names (never to OpenImageIO's
// search over every reader, which opens the file with each in turn), from the file's bytes in
// memory (an IOMemReader: OpenImageIO's JPEG reader takes no other proxy), read from the already
// opened InputFile (read-only, regular file). The header is checked before any pixels are read:
// the size against the caller's limit, the bytes OpenImageIO and we would allocate against the
// file's size (check_decoded_size, docs/robustness.md). OpenImageIO's messages become one line.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "formats.hpp"
#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/memory.hpp"

namespace leanfade::io::detail {
namespace {

// OpenImageIO's (possibly multi-line) message on one line, without a final full stop.
std::string one_line(std::string message) {
    std::string line;
    for (const char character : message) {
        if (character == '\n' || character == '\r') {
            while (!line.empty() && (line.back() == '.' || line.back() == ' ')) line.pop_back();
            if (!line.empty() && !line.ends_with(";")) line += ";";
            if (!line.empty()) line += ' ';
        } else {
            line.push_back(character);
        }
    }
    while (!line.empty() && (line.back() == ' ' || line.back() == ';' || line.back() == '.'))
        line.pop_back();
    return line.empty() ? "no details" : line;
}

constexpr OiioFormat kJpeg{"jpeg", "JPEG"};
constexpr OiioFormat kTarga{"targa", "TGA"};
constexpr OiioFormat kDds{"dds", "DDS"};
constexpr OiioFormat kTiff{"tiff", "TIFF"};
constexpr OiioFormat kPsd{"psd", "PSD"};
constexpr OiioFormat kBmp{"bmp", "BMP"};
constexpr OiioFormat kHdr{"hdr", "Radiance HDR"};
constexpr OiioFormat kWebp{"webp", "WebP"};
constexpr OiioFormat kOpenExr{"openexr", "OpenEXR"};

bool has_prefix(const std::vector<std::uint8_t>& head, std::string_view magic) {
    return head.size() >= magic.size() && std::memcmp(head.data(), magic.data(), magic.size()) == 0;
}

// A file shorter than its signature, which it starts like (2 bytes at least).
bool truncated_signature(const std::vector<std::uint8_t>& head, std::string_view magic) {
    return head.size() >= 2 && head.size() < magic.size() &&
           std::memcmp(head.data(), magic.data(), head.size()) == 0;
}

// TGA has no signature at its start: a TGA 2.0 file ends with "TRUEVISION-XFILE.\0"; any TGA
// has an 18-byte header of few possible values (colour map type 0 or 1, image type 1-3 or 9-11
// agreeing with it, a pixel depth of 8, 15, 16, 24 or 32 bits, a non-zero size).
bool is_targa(const InputFile& file, const std::vector<std::uint8_t>& head) {
    static constexpr char kFooter[] = "TRUEVISION-XFILE.";  // + '\0'
    if (file.size() >= 18 + 26) {
        char footer[18];
        file.read_at(file.size() - 18, footer, sizeof footer, "file shrank while being read");
        if (std::memcmp(footer, kFooter, sizeof footer) == 0) return true;
    }
    if (head.size() < 18) return false;
    const int map_type = head[1], image_type = head[2], map_bits = head[7], depth = head[16];
    const bool mapped = image_type == 1 || image_type == 9;
    const bool known_type =
        mapped || image_type == 2 || image_type == 3 || image_type == 10 || image_type == 11;
    const bool map_ok = mapped ? map_type == 1 && (map_bits == 15 || map_bits == 16 ||
                                                   map_bits == 24 || map_bits == 32)
                               : map_type == 0 || map_type == 1;
    const bool depth_ok = depth == 8 || depth == 15 || depth == 16 || depth == 24 || depth == 32;
    const int width = head[12] | (head[13] << 8), height = head[14] | (head[15] << 8);
    return known_type && map_ok && depth_ok && width > 0 && height > 0 && (head[17] & 0xC0) == 0;
}

// OpenImageIO's TGA reader (2.4) decodes a file whose pixel data ends early without an error,
// the missing texels left as they were. The data must hold every texel: raw images their
// width x height x bytes per pixel, RLE images packets covering them all (walked here, in time
// linear in the file's size).
void check_targa_data(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    if (bytes.size() < 18) throw Error(path, "truncated TGA data (header)");
    const auto u16 = [&](std::size_t at) {
        return std::uint64_t(bytes[at] | (bytes[at + 1] << 8));
    };
    const std::uint64_t map_bytes =
        bytes[1] == 1 ? u16(5) * ((std::uint64_t(bytes[7]) + 7) / 8) : 0;
    const std::uint64_t start = 18 + std::uint64_t(bytes[0]) + map_bytes;
    const std::uint64_t texels = u16(12) * u16(14);
    const std::uint64_t texel_bytes = (std::uint64_t(bytes[16]) + 7) / 8;
    const int type = bytes[2];
    const auto truncated = [&] {
        throw Error(path, "truncated TGA data (" + std::to_string(u16(12)) + "x" +
                              std::to_string(u16(14)) + " texels need more than the " +
                              std::to_string(bytes.size()) + "-byte file holds)");
    };
    if (type == 1 || type == 2 || type == 3) {
        if (start + texels * texel_bytes > bytes.size()) truncated();
        return;
    }
    std::uint64_t covered = 0, position = start;
    while (covered < texels) {
        if (position >= bytes.size()) truncated();
        const std::uint8_t packet = bytes[position++];
        const std::uint64_t count = std::uint64_t(packet & 0x7F) + 1;
        position += (packet & 0x80) != 0 ? texel_bytes : count * texel_bytes;
        if (position > bytes.size()) truncated();
        covered += count;
    }
}

// OpenImageIO's JPEG reader (2.4) decodes a file cut short without an error (libjpeg warns and
// fills the rest grey). The marker segments before the first scan must be complete, and an
// end-of-image marker (FF D9, which entropy-coded data cannot hold) must follow that scan.
void check_jpeg_data(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::size_t position = 2;  // after SOI
    while (true) {
        while (position < bytes.size() && bytes[position] == 0xFF) ++position;  // fill bytes
        if (position + 2 >= bytes.size()) throw Error(path, "truncated JPEG data (headers)");
        const std::uint8_t marker = bytes[position++];
        if (marker == 0xDA) break;  // start of scan
        const std::size_t length = std::size_t(bytes[position] << 8 | bytes[position + 1]);
        if (length < 2) throw Error(path, "corrupt JPEG data (marker segment of length < 2)");
        position += length;
    }
    for (std::size_t i = bytes.size() - 1; i > position; --i)
        if (bytes[i] == 0xD9 && bytes[i - 1] == 0xFF) return;
    throw Error(path, "truncated JPEG data (no end-of-image marker after the image data)");
}

// BMP: "BM", then an info header of one of the known sizes at offset 14.
bool is_bmp(const std::vector<std::uint8_t>& head) {
    if (!has_prefix(head, "BM") || head.size() < 18) return false;
    const std::uint32_t info = load_u32_le(head.data() + 14);
    return info == 12 || info == 40 || info == 52 || info == 56 || info == 64 || info == 108 ||
           info == 124;
}

// ---- DDS normal maps stored as two channels ----

constexpr std::uint32_t kDdsNormalFlag = 0x80000000u;  // DDPF_NORMAL (NVIDIA's tools)

struct DdsLayout {
    std::uint32_t pixel_flags = 0;
    std::string four_cc;
};

DdsLayout dds_layout(const std::vector<std::uint8_t>& bytes) {
    DdsLayout layout;
    if (bytes.size() < 128) return layout;  // the reader refuses it
    layout.pixel_flags = load_u32_le(bytes.data() + 80);
    layout.four_cc.assign(reinterpret_cast<const char*>(bytes.data() + 84), 4);
    return layout;
}

bool channel_is_constant(const std::vector<float>& pixels, int channels, int channel) {
    for (std::size_t i = std::size_t(channel); i < pixels.size(); i += std::size_t(channels))
        if (pixels[i] != pixels[std::size_t(channel)]) return false;
    return true;
}

// Which channels of the decoded DDS hold the normal's x and y (encoded 0.5 n + 0.5), when it is a
// two-channel normal map; {-1, -1} otherwise. OpenImageIO returns BC5 as R, G; a DXT5 flagged as
// a normal map with x (from alpha) in R and y in G (and its own 8-bit z in B, recomputed here in
// float); RXGB (Doom 3's DXT5) with x moved to R. An unflagged DXT5 whose R and B are the same
// everywhere is DXT5 "nm" (x in alpha, y in green; R and B constant by construction).
std::pair<int, int> dds_normal_channels(const DdsLayout& layout, const std::string& compression,
                                        const std::vector<float>& pixels, int channels) {
    if (compression == "BC5" && channels == 2) return {0, 1};
    if (compression != "DXT5") return {-1, -1};
    if (layout.four_cc == "RXGB" && channels >= 2) return {0, 1};
    if ((layout.pixel_flags & kDdsNormalFlag) != 0 && channels >= 2) return {0, 1};
    if (channels == 4 && channel_is_constant(pixels, 4, 0) && channel_is_constant(pixels, 4, 2))
        return {3, 1};
    return {-1, -1};
}

// z = sqrt(1 - x^2 - y^2) for each texel (x, y encoded 0.5 n + 0.5): an RGB normal map encoded
// the same way. (x, y) outside the unit disc gives z = 0 (the bake raises and counts such z).
Image reconstruct_normals(const std::vector<float>& pixels, int width, int height, int channels,
                          int x_channel, int y_channel) {
    Image normals(width, height, 3);
    const std::size_t texels = normals.texel_count();
    for (std::size_t i = 0; i < texels; ++i) {
        const float* texel = pixels.data() + i * std::size_t(channels);
        const float encoded_x = texel[x_channel], encoded_y = texel[y_channel];
        const float x = 2.0f * encoded_x - 1.0f, y = 2.0f * encoded_y - 1.0f;
        const float z = std::sqrt(std::max(0.0f, 1.0f - x * x - y * y));
        normals.pixels[3 * i + 0] = encoded_x;
        normals.pixels[3 * i + 1] = encoded_y;
        normals.pixels[3 * i + 2] = 0.5f * z + 0.5f;
    }
    return normals;
}

// ---- decoding ----

struct Decoder {
    const std::string& path;
    const OiioFormat& format;
    std::unique_ptr<OIIO::ImageInput> input;

    [[noreturn]] void fail(const std::string& what) const {
        throw Error(path, what + " (" + one_line(input != nullptr ? input->geterror() : "") + ")");
    }
};

// Integer samples of `channels` channels, as stored: 8-bit samples are read into the first half
// of the buffer, then widened from the end.
bool read_integer_samples(OIIO::ImageInput& input, UnormImage& image) {
    const bool eight_bit = image.max_value == 255;
    if (!input.read_image(0, 0, 0, image.channels,
                          eight_bit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16,
                          image.samples.data()))
        return false;
    if (eight_bit) {
        const auto* bytes = reinterpret_cast<const std::uint8_t*>(image.samples.data());
        for (std::size_t i = image.samples.size(); i-- > 0;) image.samples[i] = bytes[i];
    }
    return true;
}

// The channels `order` of `all` (RGBA -> RGB with drop_alpha).
template <class Target, class Source>
Target select(const Source& all, Target target, const std::vector<int>& order) {
    const auto in = std::size_t(all.channels), out = std::size_t(target.channels);
    auto& to = [&]() -> auto& {
        if constexpr (std::is_same_v<Target, Image>)
            return target.pixels;
        else
            return target.samples;
    }
    ();
    const auto& from = [&]() -> const auto& {
        if constexpr (std::is_same_v<Source, Image>)
            return all.pixels;
        else
            return all.samples;
    }
    ();
    const std::size_t texels = std::size_t(all.width) * std::size_t(all.height);
    for (std::size_t i = 0; i < texels; ++i)
        for (std::size_t c = 0; c < out; ++c)
            to[i * out + c] = from[i * in + std::size_t(order[c])];
    return target;
}

std::variant<Image, UnormImage> decode(const std::vector<std::uint8_t>& bytes,
                                       const std::string& path, const OiioFormat& format,
                                       const ReadOptions& options, bool compact) {
    Decoder decoder{path, format, OIIO::ImageInput::create(format.plugin)};
    if (decoder.input == nullptr) {
        throw Error(path, std::string("cannot read ") + format.name + " (" +
                              one_line(OIIO::geterror()) + ")");
    }
    OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
    if (!decoder.input->set_ioproxy(&proxy))
        decoder.fail(std::string("cannot read ") + format.name);
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // values as stored, never premultiplied
    OIIO::ImageSpec spec;
    const std::string truncated = std::string("truncated or corrupt ") + format.name + " data";
    if (!decoder.input->open(path, spec, config)) decoder.fail(truncated);

    // Header checks, before any pixel memory.
    if (spec.depth > 1) throw Error(path, std::string("volume ") + format.name + " not supported");
    check_dimensions(path, spec.width, spec.height, options.max_dimension);
    if (spec.nchannels < 1) throw Error(path, std::string(format.name) + " without channels");
    if (spec.nchannels > 64) {
        throw Error(path, std::string(format.name) + " with " + std::to_string(spec.nchannels) +
                              " channels (at most 4 are used, 64 accepted)");
    }
    std::vector<std::string> names(spec.channelnames.begin(), spec.channelnames.end());
    names.resize(std::size_t(spec.nchannels));
    std::vector<int> order = order_channels(path, names, format.name);
    const auto texels = std::uint64_t(spec.width) * std::uint64_t(spec.height);
    const auto all_channels = std::uint64_t(spec.nchannels);
    std::uint64_t decoded = texels * all_channels * sizeof(float);
    decoded = std::max<std::uint64_t>(decoded, spec.image_bytes(true));
    if (spec.tile_width > 0) {
        const std::uint64_t tile = std::uint64_t(spec.tile_width) *
                                   std::uint64_t(spec.tile_height) *
                                   std::uint64_t(std::max(spec.tile_depth, 1)) * all_channels * 8;
        decoded = std::max(decoded, tile);
    }
    check_decoded_size(path,
                       std::string(format.name) + " of " + std::to_string(spec.width) + "x" +
                           std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) +
                           " channels",
                       decoded, bytes.size());
    for (int c = 0; c < spec.nchannels && format.plugin == kOpenExr.plugin; ++c) {
        if (spec.channelformat(c).basetype == OIIO::TypeDesc::UINT32)
            throw Error(path,
                        "OpenEXR uint channels with B44, PXR24 or DWA compression not "
                        "supported");
    }

    const int width = spec.width, height = spec.height;
    const std::string compression = spec.get_string_attribute("compression");
    const bool dds = format.plugin == kDds.plugin;
    if (options.drop_alpha && order.size() == 4) order.pop_back();
    // Integer samples are kept as such (as PNG's: the float of a sample is sample / max, exactly
    // UnormImage::to_float's), the others read as floats.
    const bool integer = spec.channelformats.empty() && (spec.format == OIIO::TypeDesc::UINT8 ||
                                                         spec.format == OIIO::TypeDesc::UINT16);
    std::vector<float> floats;
    std::variant<Image, UnormImage> result;
    if (integer) {
        UnormImage all(width, height, spec.nchannels,
                       spec.format == OIIO::TypeDesc::UINT8 ? 255 : 65535);
        if (!read_integer_samples(*decoder.input, all)) decoder.fail(truncated);
        if (dds) {
            floats = all.to_float().pixels;
        } else {
            UnormImage selected =
                select(all, UnormImage(width, height, int(order.size()), all.max_value), order);
            all = {};
            if (compact) return selected;
            return selected.to_float();
        }
    } else {
        assign_large(floats, std::size_t(texels * all_channels), 0.0f);
        if (!decoder.input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT,
                                       floats.data()))
            decoder.fail(truncated);
    }
    decoder.input->close();

    const auto [x_channel, y_channel] =
        dds ? dds_normal_channels(dds_layout(bytes), compression, floats, spec.nchannels)
            : std::pair<int, int>{-1, -1};
    if (x_channel >= 0)
        return reconstruct_normals(floats, width, height, spec.nchannels, x_channel, y_channel);
    Image all(width, height, spec.nchannels);
    all.pixels = std::move(floats);
    Image image = select(all, Image(width, height, int(order.size())), order);
    all = {};
    check_finite(path, image);
    return image;
}

// OpenImageIO's exceptions (allocation failures, its own checks) as one-line errors.
template <class Call>
auto guarded(const std::string& path, const OiioFormat& format, Call&& call) {
    try {
        return call();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error(path, std::string("out of memory decoding ") + format.name);
    } catch (const std::exception& error) {
        throw Error(
            path, std::string("corrupt ") + format.name + " data (" + one_line(error.what()) + ")");
    }
}

}  // namespace

const std::vector<std::string>& oiio_format_names() {
    static const std::vector<std::string> names{kJpeg.name, kTarga.name, kDds.name, kTiff.name,
                                                kPsd.name,  kBmp.name,   kHdr.name, kWebp.name};
    return names;
}

const OiioFormat* recognise_oiio_format(const InputFile& file,
                                        const std::vector<std::uint8_t>& head) {
    const std::string& path = file.path();
    static constexpr std::string_view kJpegMagic("\xFF\xD8\xFF", 3);
    static constexpr std::string_view kTiffLittle("II*\0", 4), kTiffBig("MM\0*", 4);
    static constexpr std::string_view kBigTiffLittle("II+\0", 4), kBigTiffBig("MM\0+", 4);
    if (has_prefix(head, kJpegMagic)) return &kJpeg;
    if (truncated_signature(head, kJpegMagic)) throw Error(path, "truncated JPEG data");
    if (has_prefix(head, "DDS ")) return &kDds;
    if (truncated_signature(head, "DDS ")) throw Error(path, "truncated DDS data");
    for (const std::string_view magic : {kTiffLittle, kTiffBig, kBigTiffLittle, kBigTiffBig}) {
        if (has_prefix(head, magic)) return &kTiff;
        if (truncated_signature(head, magic)) throw Error(path, "truncated TIFF data");
    }
    if (has_prefix(head, "8BPS")) return &kPsd;
    if (truncated_signature(head, "8BPS")) throw Error(path, "truncated PSD data");
    if (is_bmp(head)) return &kBmp;
    if (has_prefix(head, "#?RADIANCE") || has_prefix(head, "#?RGBE")) return &kHdr;
    if (has_prefix(head, "RIFF") && head.size() >= 12 && std::memcmp(&head[8], "WEBP", 4) == 0)
        return &kWebp;
    if (is_targa(file, head)) return &kTarga;
    return nullptr;
}

std::variant<Image, UnormImage> decode_oiio(const InputFile& file, const OiioFormat& format,
                                            const ReadOptions& options, bool compact) {
    const std::vector<std::uint8_t> bytes = file.read_all();
    if (format.plugin == kTarga.plugin) check_targa_data(file.path(), bytes);
    if (format.plugin == kJpeg.plugin) check_jpeg_data(file.path(), bytes);
    return guarded(file.path(), format,
                   [&] { return decode(bytes, file.path(), format, options, compact); });
}

Image decode_exr_with_openimageio(const std::string& path, const std::vector<std::uint8_t>& bytes,
                                  const ReadOptions& options) {
    return guarded(path, kOpenExr,
                   [&] { return std::get<Image>(decode(bytes, path, kOpenExr, options, false)); });
}

}  // namespace leanfade::io::detail
