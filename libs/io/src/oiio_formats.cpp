// The formats read through OpenImageIO (formats.hpp): recognised by content here, decoded by the
// OpenImageIO module (oiio_image.cpp), which leanfade_io loads on first use.
//
// The module is a separate shared object because OpenImageIO 2.4 (Debian 12) brings about 260
// shared libraries (OpenVDB, GDAL, FFmpeg, OpenCV, ...): linked into leanfade they cost every
// command about 130 MB of resident memory and 0.6 s of CPU time at start-up, before any image is
// read. Loaded with dlopen, only a command that reads such a file pays it.
#include <dlfcn.h>
#include <link.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "formats.hpp"
#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"

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
// fuzz_image_bake). Each section must fit in the file, after the 26-byte header; read from the
// file, before OpenImageIO opens it.
void check_psd_sections(const InputFile& file) {
    const std::string& path = file.path();
    const std::uint64_t file_size = file.size();
    if (file_size < 26) throw Error(path, "truncated PSD data (header)");
    std::uint8_t header[26];
    file.read_at(0, header, sizeof header, "file shrank while being read");
    const int version = header[4] << 8 | header[5];
    if (version != 1 && version != 2)
        throw Error(path, "corrupt PSD header (version " + std::to_string(version) + ")");
    static constexpr const char* kSections[3] = {"colour mode data", "image resources",
                                                 "layer and mask information"};
    std::uint64_t position = 26;
    for (int section = 0; section < 3; ++section) {
        // PSB (version 2) gives the layer and mask information's length in 8 bytes.
        const int field = section == 2 && version == 2 ? 8 : 4;
        if (position + std::uint64_t(field) > file_size)
            throw Error(path, std::string("truncated PSD data (") + kSections[section] + ")");
        std::uint8_t length_bytes[8];
        file.read_at(position, length_bytes, std::size_t(field), "file shrank while being read");
        std::uint64_t length = 0;
        for (int i = 0; i < field; ++i) length = length << 8 | length_bytes[i];
        position += std::uint64_t(field);
        if (length > file_size - position) {
            throw Error(path, std::string("truncated or corrupt PSD data (") + kSections[section] +
                                  " of " + std::to_string(length) + " bytes past the end of the " +
                                  std::to_string(file_size) + "-byte file)");
        }
        position += length;
    }
}

// OpenImageIO's WebP reader (2.4) reads the whole file when it opens it: the size is read here
// from the first chunk (VP8X's canvas, VP8L's or VP8's frame), before. A file too short for it,
// or of another first chunk, is left to the reader's own checks.
void check_webp_size(const InputFile& file, const ReadOptions& options) {
    std::uint8_t head[30] = {};
    if (file.size() < sizeof head) return;
    file.read_at(0, head, sizeof head, "file shrank while being read");
    const std::string_view chunk(reinterpret_cast<const char*>(head + 12), 4);
    std::int64_t width = 0, height = 0;
    if (chunk == "VP8X") {
        width = std::int64_t(head[24] | head[25] << 8 | head[26] << 16) + 1;
        height = std::int64_t(head[27] | head[28] << 8 | head[29] << 16) + 1;
    } else if (chunk == "VP8L" && head[20] == 0x2F) {
        const std::uint32_t bits = load_u32_le(head + 21);
        width = std::int64_t(bits & 0x3FFF) + 1;
        height = std::int64_t((bits >> 14) & 0x3FFF) + 1;
    } else if (chunk == "VP8 " && head[23] == 0x9D && head[24] == 0x01 && head[25] == 0x2A) {
        width = load_u16_le(head + 26) & 0x3FFF;
        height = load_u16_le(head + 28) & 0x3FFF;
    } else {
        return;
    }
    check_dimensions(file.path(), width, height, options.max_dimension);
}

// BMP: "BM", then an info header of one of the known sizes at offset 14.
bool is_bmp(const std::vector<std::uint8_t>& head) {
    if (!has_prefix(head, "BM") || head.size() < 18) return false;
    const std::uint32_t info = load_u32_le(head.data() + 14);
    return info == 12 || info == 40 || info == 52 || info == 56 || info == 64 || info == 108 ||
           info == 124;
}

// The module, found relative to the code that loads it, never by a path of the build:
// - beside the object holding this function (dladdr): <lib>/leanfade/ of a shared libleanfade_io,
//   and <bin>/../lib/leanfade/ of a program (the installed `leanfade`, or an engine that links
//   the static library from its own tree);
// - in the run path and library path of that object (dlinfo), then by its file name: the run
//   path of the program (the package puts <prefix>/lib/leanfade on the
//   run path of what links it; the build tree puts libs/io on its targets'), LD_LIBRARY_PATH.
// Loaded once; a failure is reported on every use.
const OiioModule* load_module(std::string& failure) {
    std::vector<std::string> candidates;
    // The object holding this function: its file and its link map (glibc's handles are link
    // maps: the one dladdr1 gives is the object's handle).
    Dl_info self{};
    link_map* self_map = nullptr;
    const bool found = ::dladdr1(reinterpret_cast<const void*>(&load_module), &self,
                                 reinterpret_cast<void**>(&self_map), RTLD_DL_LINKMAP) != 0;
    // Its file: glibc names the main program by its argv[0], which may be relative, so that one
    // is /proc/self/exe.
    std::filesystem::path object;
    if (found && self.dli_fname != nullptr && self.dli_fname[0] == '/') object = self.dli_fname;
    std::error_code no_link;
    if (object.empty()) object = std::filesystem::read_symlink("/proc/self/exe", no_link);
    if (!object.empty()) {
        const std::filesystem::path folder = object.parent_path();
        candidates.push_back((folder / "leanfade" / kOiioModuleFileName).string());
        candidates.push_back((folder / ".." / "lib" / "leanfade" / kOiioModuleFileName).string());
    }
    // The run path and library path of that object, as the dynamic linker would search them for
    // its own dlopen by name (RTLD_DI_SERINFO). Searched here explicitly: a dlopen intercepted by
    // a sanitizer runtime searches the runtime's run path, not the program's.
    if (found && self_map != nullptr) {
        Dl_serinfo size{};
        if (::dlinfo(self_map, RTLD_DI_SERINFOSIZE, &size) == 0 && size.dls_cnt > 0) {
            std::vector<std::max_align_t> storage(size.dls_size / sizeof(std::max_align_t) + 1);
            auto* paths = reinterpret_cast<Dl_serinfo*>(storage.data());
            if (::dlinfo(self_map, RTLD_DI_SERINFOSIZE, paths) == 0 &&
                ::dlinfo(self_map, RTLD_DI_SERINFO, paths) == 0) {
                for (unsigned i = 0; i < paths->dls_cnt; ++i) {
                    const char* folder = paths->dls_serpath[i].dls_name;
                    if (folder != nullptr && folder[0] == '/')
                        candidates.push_back(
                            (std::filesystem::path(folder) / kOiioModuleFileName).string());
                }
            }
        }
    }
    candidates.emplace_back(kOiioModuleFileName);
    for (const std::string& candidate : candidates) {
        std::error_code error;
        const bool by_name = candidate == kOiioModuleFileName;
        if (!by_name && !std::filesystem::exists(candidate, error)) continue;
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

// ---- DDS: the header checked before the file is read ----
//
// OpenImageIO's DDS reader takes the channel masks as they are (a mask of 0 made it loop forever)
// and decodes a file cut short as if the missing blocks were 0 (a flat map, exit 0). So the
// header is checked here, on its 128 (+ 20) bytes, before the file is read into memory: the
// size limit, the pixel format (a compression OpenImageIO decodes, or masks that are non-zero
// for each channel the flags name, within the bit count and not overlapping) and the exact
// byte count of every level, face and array element it declares.

constexpr std::uint32_t kDdsHeaderBytes = 128, kDx10HeaderBytes = 20;
constexpr std::uint32_t kDdsdMipMapCount = 0x20000, kDdsdDepth = 0x800000;
constexpr std::uint32_t kDdpfAlphaPixels = 0x1, kDdpfAlpha = 0x2, kDdpfFourCc = 0x4,
                        kDdpfRgb = 0x40, kDdpfYuv = 0x200, kDdpfLuminance = 0x20000;
constexpr std::uint32_t kCaps2Cubemap = 0x200, kCaps2Volume = 0x200000;

std::string hex_text(std::uint32_t value) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%08X", value);
    return text;
}

// The bytes of one 4x4 block of a compression OpenImageIO's DDS reader decodes; 0 for others.
std::uint32_t dds_block_bytes(std::string_view four_cc) {
    for (std::string_view bc : {"DXT1", "ATI1", "BC4U", "BC4S"})
        if (four_cc == bc) return 8;
    for (std::string_view bc : {"DXT2", "DXT3", "DXT4", "DXT5", "ATI2", "BC5U", "BC5S", "RXGB"})
        if (four_cc == bc) return 16;
    return 0;
}
std::uint32_t dxgi_block_bytes(std::uint32_t format) {
    if ((format >= 70 && format <= 72) || (format >= 79 && format <= 81)) return 8;  // BC1, BC4
    if ((format >= 73 && format <= 78) || (format >= 82 && format <= 84) ||
        (format >= 94 && format <= 99))
        return 16;  // BC2, BC3, BC5, BC6H, BC7
    return 0;
}

// a * b, saturated at UINT64_MAX (every size below is compared with the file's size).
std::uint64_t times(std::uint64_t a, std::uint64_t b) {
    std::uint64_t product = 0;
    return __builtin_mul_overflow(a, b, &product) ? UINT64_MAX : product;
}
std::uint64_t plus(std::uint64_t a, std::uint64_t b) {
    return a > UINT64_MAX - b ? UINT64_MAX : a + b;
}

void check_dds_header(const InputFile& file, const ReadOptions& options) {
    const std::string& path = file.path();
    if (file.size() < kDdsHeaderBytes)
        throw Error(path, "truncated DDS data (a header of 128 bytes, the file holds " +
                              std::to_string(file.size()) + ")");
    std::uint8_t header[kDdsHeaderBytes + kDx10HeaderBytes] = {};
    file.read_at(0, header, kDdsHeaderBytes, "file shrank while being read");
    const auto u32 = [&](std::size_t offset) { return load_u32_le(header + offset); };
    if (u32(4) != 124 || u32(76) != 32)
        throw Error(path, "corrupt DDS header (header size " + std::to_string(u32(4)) +
                              " and pixel format size " + std::to_string(u32(76)) +
                              ", expected 124 and 32)");
    const std::uint32_t flags = u32(8), height = u32(12), width = u32(16), depth = u32(24);
    const std::uint32_t pixel_flags = u32(80), caps2 = u32(112);
    check_dimensions(path, width, height, options.max_dimension);
    if ((caps2 & kCaps2Volume) != 0 || ((flags & kDdsdDepth) != 0 && depth > 1))
        throw Error(path, "volume DDS not supported");

    const std::string four_cc(reinterpret_cast<const char*>(header + 84), 4);
    std::uint64_t header_bytes = kDdsHeaderBytes;
    std::uint32_t block_bytes = 0, texel_bytes = 0;
    std::uint64_t images = 1;  // faces x array elements
    std::string format_text;
    if ((pixel_flags & kDdpfFourCc) != 0) {
        if (four_cc == "DX10") {
            header_bytes += kDx10HeaderBytes;
            if (file.size() < header_bytes)
                throw Error(path, "truncated DDS data (a DX10 header of 148 bytes, the file "
                                  "holds " + std::to_string(file.size()) + ")");
            file.read_at(kDdsHeaderBytes, header + kDdsHeaderBytes, kDx10HeaderBytes,
                         "file shrank while being read");
            const std::uint32_t dxgi = u32(128), dimension = u32(132), misc = u32(136),
                                array_size = u32(140);
            if (dimension == 4) throw Error(path, "volume DDS not supported");
            block_bytes = dxgi_block_bytes(dxgi);
            if (block_bytes == 0)
                throw Error(path, "unsupported DDS format (DXGI format " + std::to_string(dxgi) +
                                      "; BC1-BC7 are read)");
            if (array_size == 0) throw Error(path, "corrupt DDS header (DX10 array size 0)");
            images = times(array_size, (misc & 0x4) != 0 ? 6 : 1);
            format_text = "DXGI format " + std::to_string(dxgi);
        } else {
            block_bytes = dds_block_bytes(four_cc);
            if (block_bytes == 0)
                throw Error(path, "unsupported DDS compression '" + escape_text(four_cc) +
                                      "' (DXT1-DXT5, ATI1/BC4, ATI2/BC5, RXGB and DX10 are read)");
            format_text = four_cc;
        }
    } else {
        const std::uint32_t bits = u32(88);
        if (bits != 8 && bits != 16 && bits != 24 && bits != 32)
            throw Error(path, "corrupt DDS pixel format (" + std::to_string(bits) +
                                  " bits per texel, expected 8, 16, 24 or 32)");
        if ((pixel_flags & (kDdpfRgb | kDdpfLuminance | kDdpfAlpha | kDdpfYuv)) == 0)
            throw Error(path, "corrupt DDS pixel format (flags " + hex_text(pixel_flags) +
                                  " name no compression and no channels)");
        struct Mask {
            const char* name;
            std::uint32_t value;
            bool used;
        };
        const bool colour = (pixel_flags & (kDdpfRgb | kDdpfYuv)) != 0;
        const bool luminance = (pixel_flags & kDdpfLuminance) != 0;
        const bool alpha = (pixel_flags & (kDdpfAlphaPixels | kDdpfAlpha)) != 0;
        const Mask masks[] = {{"red", u32(92), colour || luminance},
                              {"green", u32(96), colour},
                              {"blue", u32(100), colour},
                              {"alpha", u32(104), alpha}};
        const std::uint64_t within = bits == 32 ? 0xFFFFFFFFull : (1ull << bits) - 1;
        std::uint32_t taken = 0;
        for (const Mask& mask : masks) {
            if (mask.used && mask.value == 0)
                throw Error(path, std::string("corrupt DDS pixel format (the ") + mask.name +
                                      " channel's mask is 0)");
            if (!mask.used) continue;
            if (mask.value > within)
                throw Error(path, std::string("corrupt DDS pixel format (the ") + mask.name +
                                      " channel's mask " + hex_text(mask.value) +
                                      " lies beyond the " + std::to_string(bits) +
                                      " bits of a texel)");
            // Luminance shares the red mask's bits with nothing; the others must not overlap.
            if ((taken & mask.value) != 0)
                throw Error(path, std::string("corrupt DDS pixel format (the ") + mask.name +
                                      " channel's mask " + hex_text(mask.value) +
                                      " overlaps another channel's)");
            taken |= mask.value;
        }
        texel_bytes = bits / 8;
        format_text = std::to_string(bits) + "-bit uncompressed";
    }
    if ((caps2 & kCaps2Cubemap) != 0) {
        std::uint64_t faces = 0;
        for (int f = 0; f < 6; ++f) faces += (caps2 >> (10 + f)) & 1u;
        images = times(images, std::max<std::uint64_t>(faces, 1));
    }
    // Every level the header declares (at most the full chain), each face and element.
    std::uint32_t chain = 1;
    for (std::uint32_t side = std::max(width, height); side > 1; side /= 2) ++chain;
    std::uint32_t levels = 1;
    if ((flags & kDdsdMipMapCount) != 0 && u32(28) > 1) levels = std::min(u32(28), chain);
    std::uint64_t image_bytes = 0;
    for (std::uint32_t level = 0; level < levels; ++level) {
        const std::uint64_t w = std::max<std::uint64_t>(width >> level, 1);
        const std::uint64_t h = std::max<std::uint64_t>(height >> level, 1);
        image_bytes = plus(image_bytes, block_bytes != 0
                                            ? times(times((w + 3) / 4, (h + 3) / 4), block_bytes)
                                            : times(times(w, h), texel_bytes));
    }
    const std::uint64_t needed = times(image_bytes, images);
    const std::uint64_t data = file.size() - header_bytes;
    if (file.size() < header_bytes || data < needed)
        throw Error(path, "truncated DDS data (" + format_text + " of " + std::to_string(width) +
                              "x" + std::to_string(height) + ", " + std::to_string(levels) +
                              (levels == 1 ? " level" : " levels") +
                              (images > 1 ? " x " + std::to_string(images) + " images" : "") +
                              ": " + std::to_string(needed) + " bytes of data after the " +
                              std::to_string(header_bytes) + "-byte header, the file holds " +
                              std::to_string(file.size() < header_bytes ? 0 : data) + ")");
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
    const auto is = [&](const OiioFormat& other) {
        return std::strcmp(format.plugin, other.plugin) == 0;
    };
    // The header, from the file, before the file is read into memory (docs/robustness.md).
    if (is(kDds)) {
        check_dds_header(file, options);
    } else if (is(kWebp)) {
        check_webp_size(file, options);
    } else {
        if (is(kPsd)) check_psd_sections(file);
        module.check_header(file, format, options);
    }
    const std::vector<std::uint8_t> bytes = file.read_all();
    if (is(kTarga)) check_targa_data(file.path(), bytes);
    if (is(kJpeg)) check_jpeg_data(file.path(), bytes);
    return module.decode(bytes, file.path(), format, options, compact);
}

Image decode_exr_with_openimageio(const std::string& path, const std::vector<std::uint8_t>& bytes,
                                  const ReadOptions& options) {
    const OiioModule& module = module_for(path, kOpenExr.name);
    return std::get<Image>(module.decode(bytes, path, kOpenExr, options, false));
}

}  // namespace leanfade::io::detail
