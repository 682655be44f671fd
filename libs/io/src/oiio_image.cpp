// The OpenImageIO module (libleanfade_io_oiio.so, loaded by oiio_formats.cpp on first use):
// decodes JPEG, TGA, DDS (BC1-BC5), TIFF, PSD, BMP, Radiance HDR, WebP and the OpenEXR files of
// the compressions tinyexr cannot decode, from the file's bytes in memory; and checks a file's
// header (check_header) through the file itself, before the caller reads it into memory.
//
// Each file goes to the one reader of the format its content named (never to OpenImageIO's
// search over every reader, which opens the file with each in turn), through an IOMemReader
// (OpenImageIO's JPEG reader takes no other proxy). The header is checked before any pixels are
// read: the size against the caller's limit, the bytes OpenImageIO and we would allocate against
// the file's size (check_decoded_size, docs/robustness.md). OpenImageIO's messages become one
// line; its exceptions become leanfade::Error.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "formats.hpp"
#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/memory.hpp"

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

bool is(const OiioFormat& format, std::string_view plugin) {
    return format.plugin == plugin;
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

// DDPF_NORMAL (NVIDIA's tools set it on every normal map they write, whatever the format) changes
// how OpenImageIO decodes a file: it reports 3 channels for DXT1-DXT3, BC4 and BC7 but copies the
// decoder's 4-channel texels with a 3-channel stride, so the channels shift texel by texel. So
// the flag is cleared in a private copy of the header (never in the file) and the channels come
// from the compression alone; which of them hold the normal is decided here, from the flag.
const std::vector<std::uint8_t>& without_normal_flag(const std::vector<std::uint8_t>& bytes,
                                                     const DdsLayout& layout,
                                                     std::vector<std::uint8_t>& copy) {
    if ((layout.pixel_flags & kDdsNormalFlag) == 0) return bytes;
    copy = bytes;
    const std::uint32_t flags = layout.pixel_flags & ~kDdsNormalFlag;
    for (int i = 0; i < 4; ++i) copy[80 + std::size_t(i)] = std::uint8_t(flags >> (8 * i));
    return copy;
}

// Which channels of the decoded DDS (read without DDPF_NORMAL) hold the normal's x and y (encoded
// 0.5 n + 0.5), when it is a two-channel normal map; {-1, -1} otherwise (the channels are the
// normal's x, y, z as stored). OpenImageIO returns BC5 as R, G; RXGB (Doom 3's DXT5) with x
// moved to R. A DXT5 flagged as a normal map, or unflagged with R and B the same everywhere, is
// DXT5 "nm": x in alpha, y in green. A flagged DXT1-DXT3 with a constant blue (NVIDIA's DXT1nm)
// holds x, y in red and green.
std::pair<int, int> dds_normal_channels(const DdsLayout& layout, const std::string& compression,
                                        const std::vector<float>& pixels, int channels) {
    const bool flagged = (layout.pixel_flags & kDdsNormalFlag) != 0;
    if (compression == "BC5" && channels == 2) return {0, 1};
    if (compression == "DXT5") {
        if (layout.four_cc == "RXGB" && channels >= 2) return {0, 1};
        if (flagged && channels == 4) return {3, 1};
        if (channels == 4 && channel_is_constant(pixels, 4, 0) &&
            channel_is_constant(pixels, 4, 2))
            return {3, 1};
        return {-1, -1};
    }
    if (flagged && channels >= 3 && compression.starts_with("DXT") &&
        channel_is_constant(pixels, channels, 2))
        return {0, 1};
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
    std::unique_ptr<OIIO::ImageInput> input;

    [[noreturn]] void fail(const std::string& what) const {
        throw Error(path, what + " (" + one_line(input != nullptr ? input->geterror() : "") + ")");
    }
};

// The samples of every channel, interleaved: integers as stored (8-bit ones widened to 16 bits
// in place, from the end), or floats.
template <class Sample>
bool read_all_channels(OIIO::ImageInput& input, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                       std::vector<Sample>& samples) {
    const std::size_t count =
        std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels);
    assign_large(samples, count, Sample(0));
    if (!input.read_image(0, 0, 0, spec.nchannels, type, samples.data())) return false;
    if (type == OIIO::TypeDesc::UINT8) {
        const auto* bytes = reinterpret_cast<const std::uint8_t*>(samples.data());
        for (std::size_t i = count; i-- > 0;) samples[i] = Sample(bytes[i]);
    }
    return true;
}

// The channels `order` of interleaved `samples` of `channels` channels, into `target`.
template <class Sample>
void select_channels(const std::vector<Sample>& samples, int channels,
                     const std::vector<int>& order, std::vector<Sample>& target) {
    const auto in = std::size_t(channels), out = order.size();
    const std::size_t texels = samples.size() / in;
    for (std::size_t i = 0; i < texels; ++i)
        for (std::size_t c = 0; c < out; ++c)
            target[i * out + c] = samples[i * in + std::size_t(order[c])];
}

// The checks of a reader's header (`spec`, after open, before any pixel is read): size against
// the limit, channel count and names, the bytes decoding would allocate against the file's size.
// Returns the channels to keep, in order (order_channels).
std::vector<int> check_spec(const std::string& path, const OiioFormat& format,
                            const OIIO::ImageSpec& spec, const ReadOptions& options,
                            std::uint64_t file_bytes) {
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
                       decoded, file_bytes);
    for (int c = 0; c < spec.nchannels && is(format, "openexr"); ++c) {
        if (spec.channelformat(c).basetype == OIIO::TypeDesc::UINT32)
            throw Error(path,
                        "OpenEXR uint channels with B44, PXR24 or DWA compression not "
                        "supported");
    }
    return order;
}

std::variant<Image, UnormImage> decode(const std::vector<std::uint8_t>& bytes,
                                       const std::string& path, const OiioFormat& format,
                                       const ReadOptions& options, bool compact) {
    const bool dds = is(format, "dds");
    const DdsLayout layout = dds ? dds_layout(bytes) : DdsLayout{};
    std::vector<std::uint8_t> unflagged;
    const std::vector<std::uint8_t>& input = dds ? without_normal_flag(bytes, layout, unflagged)
                                                 : bytes;
    Decoder decoder{path, OIIO::ImageInput::create(format.plugin)};
    if (decoder.input == nullptr) {
        throw Error(path, std::string("cannot read ") + format.name + " (" +
                              one_line(OIIO::geterror()) + ")");
    }
    OIIO::Filesystem::IOMemReader proxy(input.data(), input.size());
    if (!decoder.input->set_ioproxy(&proxy))
        decoder.fail(std::string("cannot read ") + format.name);
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // values as stored, never premultiplied
    OIIO::ImageSpec spec;
    const std::string truncated = std::string("truncated or corrupt ") + format.name + " data";
    if (!decoder.input->open(path, spec, config)) decoder.fail(truncated);

    // Header checks, before any pixel memory (decode_oiio made them on the file already).
    std::vector<int> order = check_spec(path, format, spec, options, bytes.size());

    const int width = spec.width, height = spec.height;
    const std::string compression = spec.get_string_attribute("compression");
    if (options.drop_alpha && order.size() == 4) order.pop_back();
    // Integer samples are kept as such (as PNG's: the float of a sample is sample / max, exactly
    // UnormImage::to_float's), the others read as floats.
    const bool integer = spec.channelformats.empty() && (spec.format == OIIO::TypeDesc::UINT8 ||
                                                         spec.format == OIIO::TypeDesc::UINT16);
    std::vector<float> floats;
    if (integer) {
        const bool eight_bit = spec.format == OIIO::TypeDesc::UINT8;
        std::vector<std::uint16_t> samples;
        if (!read_all_channels(*decoder.input, spec, spec.format, samples)) decoder.fail(truncated);
        decoder.input->close();
        const std::uint16_t max_value = eight_bit ? 255 : 65535;
        if (dds) {  // normal maps are rebuilt from floats
            floats.resize(samples.size());
            for (std::size_t i = 0; i < samples.size(); ++i)
                floats[i] = float(samples[i]) / float(max_value);
        } else {
            UnormImage image(width, height, int(order.size()), max_value);
            select_channels(samples, spec.nchannels, order, image.samples);
            samples = {};
            if (compact) return image;
            return image.to_float();
        }
    } else {
        if (!read_all_channels(*decoder.input, spec, OIIO::TypeDesc::FLOAT, floats))
            decoder.fail(truncated);
        decoder.input->close();
    }

    const auto [x_channel, y_channel] =
        dds ? dds_normal_channels(layout, compression, floats, spec.nchannels)
            : std::pair<int, int>{-1, -1};
    if (x_channel >= 0)
        return reconstruct_normals(floats, width, height, spec.nchannels, x_channel, y_channel);
    Image image(width, height, int(order.size()));
    select_channels(floats, spec.nchannels, order, image.pixels);
    floats = {};
    check_finite(path, image);
    return image;
}

// decode, with OpenImageIO's exceptions (allocation failures, its own checks) as one-line errors.
std::variant<Image, UnormImage> guarded_decode(const std::vector<std::uint8_t>& bytes,
                                               const std::string& path, const OiioFormat& format,
                                               const ReadOptions& options, bool compact) {
    try {
        return decode(bytes, path, format, options, compact);
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error(path, std::string("out of memory decoding ") + format.name);
    } catch (const std::exception& error) {
        throw Error(
            path, std::string("corrupt ") + format.name + " data (" + one_line(error.what()) + ")");
    }
}

// A FILE* of its own on the descriptor of an InputFile (a duplicate: closing it leaves the
// InputFile's open), for OpenImageIO's IOFile (the proxy its JPEG reader accepts besides
// IOMemReader). The InputFile reads with pread, so the shared file offset is free to move.
class DuplicateStream {
  public:
    explicit DuplicateStream(const InputFile& file) {
        const int copy = ::fcntl(file.descriptor(), F_DUPFD_CLOEXEC, 0);
        if (copy < 0)
            throw Error(file.path(), std::string("cannot read (") + std::strerror(errno) + ")");
        stream_ = ::fdopen(copy, "rb");
        if (stream_ == nullptr) {
            const int error_number = errno;
            ::close(copy);
            throw Error(file.path(),
                        std::string("cannot read (") + std::strerror(error_number) + ")");
        }
        ::rewind(stream_);
    }
    ~DuplicateStream() { std::fclose(stream_); }
    DuplicateStream(const DuplicateStream&) = delete;
    DuplicateStream& operator=(const DuplicateStream&) = delete;
    FILE* get() const noexcept { return stream_; }

  private:
    FILE* stream_ = nullptr;
};

// Opens the file (or its bytes in memory) with the format's reader, which reads its header
// only, and makes decode's header checks on it: a file over the size limit, or claiming more
// than its bytes can hold, is refused before it is read into memory (docs/robustness.md).
void check_header(const InputFile& file, const OiioFormat& format, const ReadOptions& options) {
    const std::string& path = file.path();
    try {
        std::unique_ptr<DuplicateStream> stream;
        std::unique_ptr<OIIO::Filesystem::IOProxy> proxy;
        if (file.memory() != nullptr) {
            proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(file.memory(),
                                                                    std::size_t(file.size()));
        } else {
            stream = std::make_unique<DuplicateStream>(file);
            proxy = std::make_unique<OIIO::Filesystem::IOFile>(stream->get(),
                                                               OIIO::Filesystem::IOProxy::Read);
        }
        Decoder decoder{path, OIIO::ImageInput::create(format.plugin)};
        if (decoder.input == nullptr) {
            throw Error(path, std::string("cannot read ") + format.name + " (" +
                                  one_line(OIIO::geterror()) + ")");
        }
        if (!decoder.input->set_ioproxy(proxy.get()))
            decoder.fail(std::string("cannot read ") + format.name);
        OIIO::ImageSpec config;
        config.attribute("oiio:UnassociatedAlpha", 1);
        OIIO::ImageSpec spec;
        if (!decoder.input->open(path, spec, config))
            decoder.fail(std::string("truncated or corrupt ") + format.name + " data");
        check_spec(path, format, spec, options, file.size());
        decoder.input->close();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error(path, std::string("out of memory reading the ") + format.name + " header");
    } catch (const std::exception& error) {
        throw Error(path, std::string("corrupt ") + format.name + " header (" +
                              one_line(error.what()) + ")");
    }
}

constexpr OiioModule kModule{&guarded_decode, &check_header};

}  // namespace
}  // namespace leanfade::io::detail

extern "C" __attribute__((visibility("default"))) const leanfade::io::detail::OiioModule*
leanfade_io_oiio_module() {
    return &leanfade::io::detail::kModule;
}
