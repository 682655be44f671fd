// The formats read through OpenImageIO (formats.hpp): recognised by content here, decoded by the
// OpenImageIO module (oiio_image.cpp), which leanfade_io loads on first use.
//
// The module is a separate shared object because OpenImageIO 2.4 (Debian 12) brings about 260
// shared libraries (OpenVDB, GDAL, FFmpeg, OpenCV, ...): linked into leanfade they cost every
// command about 130 MB of resident memory and 0.6 s of CPU time at start-up, before any image is
// read. Loaded with dlopen, only a command that reads such a file pays it.
#include <dlfcn.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "formats.hpp"
#include "input_file.hpp"
#include "leanfade/core/error.hpp"

namespace leanfade::io::detail {
namespace {

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

// OpenImageIO's PSD reader (2.4) allocates the colour mode data, the image resources and the
// layer and mask information at the lengths the file gives, before it checks them against the
// file: a 152-byte file declaring 4 GB of colour data made it allocate as much (found by
// fuzz_image_bake). Each section must fit in the file, after the 26-byte header.
void check_psd_sections(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    if (bytes.size() < 26) throw Error(path, "truncated PSD data (header)");
    const int version = bytes[4] << 8 | bytes[5];
    if (version != 1 && version != 2)
        throw Error(path, "corrupt PSD header (version " + std::to_string(version) + ")");
    const auto big_endian = [&](std::size_t at, int size) {
        std::uint64_t value = 0;
        for (int i = 0; i < size; ++i) value = value << 8 | bytes[at + std::size_t(i)];
        return value;
    };
    static constexpr const char* kSections[3] = {"colour mode data", "image resources",
                                                 "layer and mask information"};
    std::uint64_t position = 26;
    for (int section = 0; section < 3; ++section) {
        // PSB (version 2) gives the layer and mask information's length in 8 bytes.
        const int field = section == 2 && version == 2 ? 8 : 4;
        if (position + std::uint64_t(field) > bytes.size())
            throw Error(path, std::string("truncated PSD data (") + kSections[section] + ")");
        const std::uint64_t length = big_endian(std::size_t(position), field);
        position += std::uint64_t(field);
        if (length > bytes.size() - position) {
            throw Error(path, std::string("truncated or corrupt PSD data (") + kSections[section] +
                                  " of " + std::to_string(length) + " bytes past the end of the " +
                                  std::to_string(bytes.size()) + "-byte file)");
        }
        position += length;
    }
}

// BMP: "BM", then an info header of one of the known sizes at offset 14.
bool is_bmp(const std::vector<std::uint8_t>& head) {
    if (!has_prefix(head, "BM") || head.size() < 18) return false;
    const std::uint32_t info = load_u32_le(head.data() + 14);
    return info == 12 || info == 40 || info == 52 || info == 56 || info == 64 || info == 108 ||
           info == 124;
}

// The module: where the build put it, then <executable's folder>/../lib/leanfade/ (an installed
// tree), then the library search path. Loaded once; a failure is reported on every use.
const OiioModule* load_module(std::string& failure) {
    std::vector<std::string> candidates{LEANFADE_IO_OIIO_MODULE_BUILD_PATH};
    std::error_code error;
    const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", error);
    if (!error) {
        candidates.push_back(
            (executable.parent_path() / ".." / "lib" / "leanfade" / kOiioModuleFileName).string());
    }
    candidates.emplace_back(kOiioModuleFileName);
    for (const std::string& candidate : candidates) {
        void* handle = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (handle == nullptr) {
            const char* message = ::dlerror();
            if (failure.empty() && message != nullptr) failure = message;
            continue;
        }
        const auto entry = reinterpret_cast<OiioModuleEntry>(::dlsym(handle, kOiioModuleEntryName));
        if (entry == nullptr) {
            failure = candidate + " has no " + kOiioModuleEntryName;
            continue;
        }
        return entry();
    }
    return nullptr;
}

const OiioModule& module_for(const std::string& path, const char* format_name) {
    static std::once_flag once;
    static const OiioModule* module = nullptr;
    static std::string failure;
    std::call_once(once, [] { module = load_module(failure); });
    if (module == nullptr) {
        throw Error(path, std::string("cannot read ") + format_name + ": the OpenImageIO module " +
                              kOiioModuleFileName + " did not load (" + failure + ")");
    }
    return *module;
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
    const OiioModule& module = module_for(file.path(), format.name);
    const std::vector<std::uint8_t> bytes = file.read_all();
    if (std::strcmp(format.plugin, kTarga.plugin) == 0) check_targa_data(file.path(), bytes);
    if (std::strcmp(format.plugin, kJpeg.plugin) == 0) check_jpeg_data(file.path(), bytes);
    if (std::strcmp(format.plugin, kPsd.plugin) == 0) check_psd_sections(file.path(), bytes);
    return module.decode(bytes, file.path(), format, options, compact);
}

Image decode_exr_with_openimageio(const std::string& path, const std::vector<std::uint8_t>& bytes,
                                  const ReadOptions& options) {
    const OiioModule& module = module_for(path, kOpenExr.name);
    return std::get<Image>(module.decode(bytes, path, kOpenExr, options, false));
}

}  // namespace leanfade::io::detail
