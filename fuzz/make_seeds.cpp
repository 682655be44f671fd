// Writes the seed corpora of the fuzz targets into fuzz/corpus/<target>/ (committed; each file a
// few hundred bytes to a few KiB). Run by `make fuzz-seeds`; deterministic, so re-running it
// rewrites the same bytes. Usage: leanfade_fuzz_seeds CORPUS_FOLDER
#include <png.h>
#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/preset.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/scene/detail/obj_loader.hpp"
#include "../tests/io/format_writers.hpp"

using namespace leanfade;
namespace fs = std::filesystem;

namespace {

void write_file(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    if (!out) throw Error(path.string(), "cannot write seed");
}

// A small height map in [0, 1] (1 channel) or a normal map encoded 0.5 n + 0.5 (3-4 channels).
Image sample_image(int width, int height, int channels) {
    Image image(width, height, channels);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float a = std::sin(0.9f * float(x)) * std::cos(0.7f * float(y));
            if (channels < 3) {
                image.at(x, y, 0) = 0.5f + 0.4f * a;
                if (channels == 2) image.at(x, y, 1) = 1.0f;
                continue;
            }
            const float nx = 0.3f * a, ny = -0.2f * a, nz = std::sqrt(1.0f - nx * nx - ny * ny);
            image.at(x, y, 0) = 0.5f * nx + 0.5f;
            image.at(x, y, 1) = 0.5f * ny + 0.5f;
            image.at(x, y, 2) = 0.5f * nz + 0.5f;
            if (channels == 4) image.at(x, y, 3) = 1.0f;
        }
    }
    return image;
}

struct RawPng {
    int width, height, bit_depth, color_type, interlace;
};

// The libpng part of write_png_raw: plain data only, so that libpng's longjmp on an error skips
// no destructor. `rows` holds height rows of row_bytes, written once per interlace pass.
bool write_png_rows(FILE* file, const RawPng& layout, const png_byte* rows, std::size_t row_bytes) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
    if (info == nullptr || setjmp(png_jmpbuf(png)) != 0) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_init_io(png, file);
    png_set_IHDR(png, info, png_uint_32(layout.width), png_uint_32(layout.height), layout.bit_depth,
                 layout.color_type, layout.interlace, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (layout.color_type == PNG_COLOR_TYPE_PALETTE) {
        png_color palette[4] = {{0, 0, 0}, {90, 128, 255}, {128, 90, 240}, {128, 128, 255}};
        png_set_PLTE(png, info, palette, 4);
        png_byte alpha[2] = {255, 128};
        png_set_tRNS(png, info, alpha, 2, nullptr);
    }
    png_write_info(png, info);
    const int passes = png_set_interlace_handling(png);
    for (int pass = 0; pass < passes; ++pass) {
        for (int y = 0; y < layout.height; ++y) {
            png_write_row(png, rows + std::size_t(y) * row_bytes);
        }
    }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

// PNG layouts io::write_png does not produce (palette + tRNS, 1/2/4-bit gray, Adam7 interlace),
// through libpng's own writer.
void write_png_raw(const fs::path& path, const RawPng& layout) {
    const int samples = layout.color_type == PNG_COLOR_TYPE_RGB ? 3 : 1;
    const std::size_t row_bytes =
        (std::size_t(layout.width) * std::size_t(samples * layout.bit_depth) + 7) / 8;
    std::vector<png_byte> rows(row_bytes * std::size_t(layout.height));
    for (std::size_t i = 0; i < rows.size(); ++i) {
        // Palette indices stay below the palette's 4 entries (2 bits per index here).
        rows[i] = layout.color_type == PNG_COLOR_TYPE_PALETTE ? png_byte(i % 4)
                                                              : png_byte(37 * i + (i >> 3));
    }
    FILE* file = std::fopen(path.c_str(), "wb");
    if (file == nullptr) throw Error(path.string(), "cannot write seed");
    const bool written = write_png_rows(file, layout, rows.data(), row_bytes);
    if (std::fclose(file) != 0 || !written) throw Error(path.string(), "libpng cannot write it");
}

// OpenEXR variants io::write_exr does not produce: half channels, other compressions, tiles.
void write_exr_raw(const fs::path& path, const Image& image, int compression, bool half,
                   bool tiled, int tile_width = 4, int tile_height = 4) {
    static const char* kNames[4] = {"A", "B", "G", "R"};  // sorted, as OpenEXR lists them
    const int channels = image.channels;
    std::vector<std::vector<float>> planes(std::size_t(channels),
                                           std::vector<float>(image.texel_count()));
    std::vector<unsigned char*> pointers;
    std::vector<EXRChannelInfo> infos(static_cast<std::size_t>(channels));
    std::vector<int> pixel_types(std::size_t(channels), TINYEXR_PIXELTYPE_FLOAT);
    std::vector<int> requested(std::size_t(channels),
                               half ? TINYEXR_PIXELTYPE_HALF : TINYEXR_PIXELTYPE_FLOAT);
    for (int c = 0; c < channels; ++c) {
        const int source = channels == 1 ? 0 : channels - 1 - c;  // A B G R <- 3 2 1 0
        for (std::size_t i = 0; i < image.texel_count(); ++i) {
            planes[std::size_t(c)][i] =
                image.pixels[i * std::size_t(channels) + std::size_t(source)];
        }
        pointers.push_back(reinterpret_cast<unsigned char*>(planes[std::size_t(c)].data()));
        std::memset(&infos[std::size_t(c)], 0, sizeof(EXRChannelInfo));
        const char* name = channels == 1 ? "Y" : kNames[4 - channels + c];
        std::strncpy(infos[std::size_t(c)].name, name, sizeof infos[0].name - 1);
    }
    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = channels;
    header.channels = infos.data();
    header.pixel_types = pixel_types.data();
    header.requested_pixel_types = requested.data();
    header.compression_type = compression;
    if (tiled) {
        header.tiled = 1;
        header.tile_size_x = tile_width;
        header.tile_size_y = tile_height;
        header.tile_level_mode = TINYEXR_TILE_ONE_LEVEL;
        header.tile_rounding_mode = TINYEXR_TILE_ROUND_DOWN;
    }
    EXRImage exr;
    InitEXRImage(&exr);
    exr.images = pointers.data();
    exr.width = image.width;
    exr.height = image.height;
    exr.num_channels = channels;
    // tinyexr writes a tiled file only from tiles (each a whole tile of each channel, rows of
    // tile_width values), counted on the header's data window.
    std::vector<std::vector<float>> tile_planes;
    std::vector<unsigned char*> tile_pointers;
    std::vector<EXRTile> tiles;
    if (tiled) {
        header.data_window.max_x = image.width - 1;
        header.data_window.max_y = image.height - 1;
        header.display_window = header.data_window;
        const int columns = (image.width + tile_width - 1) / tile_width;
        const int rows = (image.height + tile_height - 1) / tile_height;
        for (int ty = 0; ty < rows; ++ty) {
            for (int tx = 0; tx < columns; ++tx) {
                for (int c = 0; c < channels; ++c) {
                    std::vector<float> plane(std::size_t(tile_width * tile_height), 0.0f);
                    for (int y = 0; y < tile_height && ty * tile_height + y < image.height; ++y)
                        for (int x = 0; x < tile_width && tx * tile_width + x < image.width; ++x)
                            plane[std::size_t(y * tile_width + x)] =
                                planes[std::size_t(c)][std::size_t(
                                    (ty * tile_height + y) * image.width + tx * tile_width + x)];
                    tile_planes.push_back(std::move(plane));
                }
                EXRTile tile{};
                tile.offset_x = tx;
                tile.offset_y = ty;
                tile.width = std::min(tile_width, image.width - tx * tile_width);
                tile.height = std::min(tile_height, image.height - ty * tile_height);
                tiles.push_back(tile);
            }
        }
        for (auto& plane : tile_planes)
            tile_pointers.push_back(reinterpret_cast<unsigned char*>(plane.data()));
        for (std::size_t i = 0; i < tiles.size(); ++i)
            tiles[i].images = &tile_pointers[i * std::size_t(channels)];
        exr.images = nullptr;
        exr.tiles = tiles.data();
        exr.num_tiles = int(tiles.size());
    }
    unsigned char* memory = nullptr;
    const char* message = nullptr;
    const std::size_t size = SaveEXRImageToMemory(&exr, &header, &memory, &message);
    if (size == 0) {
        const std::string cause = message != nullptr ? message : "unknown";
        FreeEXRErrorMessage(message);
        throw Error(path.string(), "tinyexr cannot write the seed: " + cause);
    }
    write_file(path, std::string(reinterpret_cast<const char*>(memory), size));
    std::free(memory);
}

void image_seeds(const fs::path& dir) {
    io::write_png((dir / "gray8.png").string(), sample_image(8, 8, 1), 8);
    io::write_png((dir / "gray16.png").string(), sample_image(7, 5, 1), 16);
    io::write_png((dir / "gray_alpha8.png").string(), sample_image(6, 6, 2), 8);
    io::write_png((dir / "normal_rgb8.png").string(), sample_image(8, 8, 3), 8);
    io::write_png((dir / "normal_rgba16.png").string(), sample_image(5, 7, 4), 16);
    write_png_raw(dir / "palette_trns.png", {6, 5, 8, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE});
    write_png_raw(dir / "gray1.png", {9, 4, 1, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE});
    write_png_raw(dir / "gray4_adam7.png", {9, 9, 4, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_ADAM7});
    write_png_raw(dir / "rgb16_adam7.png", {5, 6, 16, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_ADAM7});

    io::write_exr((dir / "height_zip.exr").string(), sample_image(8, 8, 1));
    io::write_exr((dir / "normal_rgba_zip.exr").string(), sample_image(4, 4, 4));
    write_exr_raw(dir / "height_half_none.exr", sample_image(6, 5, 1), TINYEXR_COMPRESSIONTYPE_NONE,
                  true, false);
    write_exr_raw(dir / "normal_half_rle.exr", sample_image(5, 5, 3), TINYEXR_COMPRESSIONTYPE_RLE,
                  true, false);
    write_exr_raw(dir / "normal_zips.exr", sample_image(4, 6, 3), TINYEXR_COMPRESSIONTYPE_ZIPS,
                  false, false);
    write_exr_raw(dir / "height_half_piz.exr", sample_image(8, 8, 1), TINYEXR_COMPRESSIONTYPE_PIZ,
                  true, false);
    write_exr_raw(dir / "height_tiled.exr", sample_image(6, 6, 1), TINYEXR_COMPRESSIONTYPE_NONE,
                  false, true);
    // Odd tile sizes: 1 x 1, 3 x 5 (partial tiles at the edges).
    write_exr_raw(dir / "height_tiles_1x1.exr", sample_image(3, 2, 1),
                  TINYEXR_COMPRESSIONTYPE_NONE, false, true, 1, 1);
    write_exr_raw(dir / "normal_tiles_3x5_zip.exr", sample_image(7, 6, 3),
                  TINYEXR_COMPRESSIONTYPE_ZIP, true, true, 3, 5);
    // Refused (a tile size of 0, on which tinyexr 1.0.1 asserts): the fuzzer starts next to it.
    {
        write_exr_raw(dir / "refused_tile_size_0.exr", sample_image(6, 6, 1),
                      TINYEXR_COMPRESSIONTYPE_NONE, false, true);
        std::ifstream in(dir / "refused_tile_size_0.exr", std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), {});
        const std::string attribute("tiles\0tiledesc\0", 15);
        const std::size_t at = bytes.find(attribute);
        if (at == std::string::npos) throw Error("seed", "no tile description");
        bytes.replace(at + attribute.size() + 4, 4, std::string(4, '\0'));  // tile width 0
        write_file(dir / "refused_tile_size_0.exr", bytes);
    }

    io::write_pfm((dir / "height.pfm").string(), sample_image(6, 4, 1));
    io::write_pfm((dir / "normal.pfm").string(), sample_image(4, 3, 3));
    // Big-endian (positive scale) gray PFM, 2x2.
    std::string big_endian = "Pf\n2 2\n1.0\n";
    for (const float value : {0.25f, 0.5f, 0.75f, 1.0f}) {
        std::uint32_t bits;
        std::memcpy(&bits, &value, 4);
        for (int shift = 24; shift >= 0; shift -= 8) big_endian.push_back(char(bits >> shift));
    }
    write_file(dir / "height_big_endian.pfm", big_endian);

    // The formats read through OpenImageIO: written by its writers, DDS and PSD crafted
    // (tests/io/format_writers.hpp).
    const Image normal = sample_image(8, 8, 3);
    const auto oiio = [&](const char* name, const char* extension, const Image& image,
                          OIIO::TypeDesc type,
                          std::vector<std::pair<std::string, std::string>> attributes = {}) {
        // A fixed date: OpenImageIO's TIFF and OpenEXR writers record the time of writing
        // (DateTime, capDate) otherwise, and the seeds would differ from run to run.
        attributes.emplace_back("DateTime", "2000:01:01 00:00:00");
        io::test::write_with_openimageio((dir / name).string(), extension, image, type,
                                         attributes);
    };
    oiio("normal.jpg", "jpg", normal, OIIO::TypeDesc::UINT8, {{"quality", "90"}});
    oiio("height.jpg", "jpg", sample_image(8, 8, 1), OIIO::TypeDesc::UINT8);
    oiio("normal_rle.tga", "tga", sample_image(8, 8, 4), OIIO::TypeDesc::UINT8,
         {{"compression", "rle"}});
    oiio("normal.tga", "tga", normal, OIIO::TypeDesc::UINT8);
    oiio("normal16_zip.tif", "tif", normal, OIIO::TypeDesc::UINT16, {{"compression", "zip"}});
    oiio("height_float.tif", "tif", sample_image(6, 5, 1), OIIO::TypeDesc::FLOAT);
    oiio("normal.bmp", "bmp", normal, OIIO::TypeDesc::UINT8);
    oiio("normal.hdr", "hdr", normal, OIIO::TypeDesc::FLOAT);
    oiio("normal.webp", "webp", normal, OIIO::TypeDesc::UINT8);
    for (const char* compression : {"dwaa", "dwab", "b44", "b44a", "pxr24"}) {
        oiio((std::string("normal_") + compression + ".exr").c_str(), "exr", normal,
             OIIO::TypeDesc::HALF, {{"compression", compression}});
    }
    {
        std::vector<std::uint8_t> bc5, dxt5nm, bc1;
        const std::vector<int> stripes{0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 1, 1, 1, 1};
        for (int block = 0; block < 4; ++block) {
            io::test::append_bc4_block(bc5, std::uint8_t(100 + 9 * block), 128, stripes);
            io::test::append_bc4_block(bc5, std::uint8_t(150 - 9 * block), 128, stripes);
            io::test::append_bc4_block(dxt5nm, std::uint8_t(100 + 9 * block), 128, stripes);
            io::test::append_bc1_block(dxt5nm, 0xF800 | (40 << 5), 0xF800 | (24 << 5), stripes);
            io::test::append_bc1_block(bc1, 0xFFFF, 0x001F, stripes);
        }
        const auto dds = [&](const char* name, const char* four_cc,
                             const std::vector<std::uint8_t>& blocks, std::uint32_t dxgi = 0) {
            const auto bytes =
                io::test::dds_file(8, 8, four_cc, io::test::kDdsFourCcFlag, blocks, dxgi);
            write_file(dir / name, std::string(bytes.begin(), bytes.end()));
        };
        dds("normal_bc5.dds", "ATI2", bc5);
        dds("normal_bc5_dx10.dds", "DX10", bc5, 83);
        dds("normal_dxt5nm.dds", "DXT5", dxt5nm);
        dds("colour_bc1.dds", "DXT1", bc1);
        {
            // Uncompressed RGBA, 32 bits: the channel masks (checked on the header).
            std::vector<std::uint8_t> texels;
            for (int t = 0; t < 8 * 8; ++t)
                for (int c = 0; c < 4; ++c) texels.push_back(std::uint8_t((t * 37 + c * 71) & 0xFF));
            auto bytes = io::test::dds_file(8, 8, "\0\0\0\0", 0x41, texels);
            io::test::put_u32(bytes, 88, 32);
            const std::uint32_t masks[] = {0x00FF0000u, 0x0000FF00u, 0x000000FFu, 0xFF000000u};
            for (std::size_t c = 0; c < 4; ++c) io::test::put_u32(bytes, 92 + 4 * c, masks[c]);
            write_file(dir / "normal_rgba32.dds", std::string(bytes.begin(), bytes.end()));
        }
        const auto psd8 = io::test::psd_file(normal, 8);
        write_file(dir / "normal8.psd", std::string(psd8.begin(), psd8.end()));
        const auto psd16 = io::test::psd_file(sample_image(5, 4, 1), 16);
        write_file(dir / "height16.psd", std::string(psd16.begin(), psd16.end()));
    }
}

void ktx2_seeds(const fs::path& dir) {
    const struct {
        const char* name;
        int width, height;
        Storage storage;
        float shininess;
    } maps[] = {{"unorm8_8x8.ktx2", 8, 8, Storage::Unorm8, 0.0f},
                {"unorm16_5x3.ktx2", 5, 3, Storage::Unorm16, 0.0f},
                {"float16_4x4_baked.ktx2", 4, 4, Storage::Float16, 32.0f},
                {"float32_3x2.ktx2", 3, 2, Storage::Float32, 0.0f}};
    for (const auto& m : maps) {
        BakeOptions options;
        options.threads = 1;
        options.bake_roughness_shininess = m.shininess;
        Image height = make_builtin_height("bumps", 8, 3);
        Image cropped(m.width, m.height, 1);
        for (int y = 0; y < m.height; ++y)
            for (int x = 0; x < m.width; ++x) cropped.at(x, y) = height.at(x, y);
        const BakeResult result = bake_lean_map(cropped, BakeSource::Height, options);
        io::write_ktx2((dir / m.name).string(),
                       pack_lean_map(result.map, m.storage, "leanfade fuzz seed"));
    }
    // Refused maps next to the checks of read_ktx2 and inspect_ktx2: overlapping levels, a level
    // inside the header, a key given twice, a partial MIP chain (from unorm16_5x3.ktx2: 3 levels,
    // level index at 80, 24 bytes per level).
    std::ifstream in(dir / "unorm16_5x3.ktx2", std::ios::binary);
    const std::string valid((std::istreambuf_iterator<char>(in)), {});
    const auto store_u64 = [](std::string& bytes, std::size_t at, std::uint64_t value) {
        for (int i = 0; i < 8; ++i) bytes[at + std::size_t(i)] = char(value >> (8 * i));
    };
    const auto load_u64 = [](const std::string& bytes, std::size_t at) {
        std::uint64_t value = 0;
        for (int i = 7; i >= 0; --i)
            value = (value << 8) | std::uint8_t(bytes[at + std::size_t(i)]);
        return value;
    };
    std::string overlap = valid;
    store_u64(overlap, 80 + 24, load_u64(valid, 80));
    write_file(dir / "refused_overlapping_levels.ktx2", overlap);
    std::string in_header = valid;
    store_u64(in_header, 80 + 2 * 24, 16);
    write_file(dir / "refused_level_in_header.ktx2", in_header);
    std::string duplicate = valid;
    const std::string from("LEANFADEroughnessBaked", 22), to("LEANFADEbakedShininess", 22);
    duplicate.replace(duplicate.find(from), from.size(), to);
    write_file(dir / "refused_duplicate_key.ktx2", duplicate);
    std::string partial = valid;
    partial[40] = 2;  // levelCount 2 of 3
    write_file(dir / "refused_partial_chain.ktx2", partial);
}

void obj_seeds(const fs::path& dir) {
    write_file(dir / "triangle.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_file(dir / "quad_uv_normals.obj",
               "# a quad with texture coordinates and normals\no quad\n"
               "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
               "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
               "s 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n");
    write_file(dir / "negative_indices.obj",
               "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 1\nvn 0 0 1\nvn 0 1 0\n"
               "f -4//-2 -3//-2 -2//-1\nf -4//-1 -2//-1 -1//-2\n");
    write_file(dir / "pentagon_groups.obj",
               "g top\nv 0 0 0\nv 2 0 0\nv 3 1.5 0.25\nv 1 3 0.5\nv -1 1.5 0.25\n"
               "vt 0.5 0 0\nvt 1 0.4\nvt 0.8 1\nvt 0.2 1\nvt 0 0.4\n"
               "usemtl none\nf 1/1 2/2 3/3 4/4 5/5 # a fan\n");
    write_file(dir / "tetrahedron.obj",
               "v 1 1 1\nv -1 -1 1\nv -1 1 -1\nv 1 -1 -1\n"
               "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n");
    write_file(dir / "scientific_crlf.obj",
               "v 1e-3 2.5E+1 -0.0\r\nv 3.25 -1e2 7\r\nv 0.5 0.5 1e1\r\nf 1 2 3\r\n");
    // A convex face of 80 vertices (above the ear-clipping limit of 64: a fan) and a non-convex
    // star of 24 (ear-clipped).
    std::string disc, star;
    for (int i = 0; i < 80; ++i) {
        const double angle = 6.283185307179586 * i / 80;
        disc += "v " + std::to_string(std::cos(angle)) + " " + std::to_string(std::sin(angle)) +
                " 0\n";
    }
    disc += "f";
    for (int i = 1; i <= 80; ++i) disc += " " + std::to_string(i);
    write_file(dir / "large_face.obj", disc + "\n");
    for (int i = 0; i < 24; ++i) {
        const double angle = 6.283185307179586 * i / 24, radius = i % 2 == 0 ? 1.0 : 0.4;
        star += "v " + std::to_string(radius * std::cos(angle)) + " " +
                std::to_string(radius * std::sin(angle)) + " 0\n";
    }
    star += "f";
    for (int i = -24; i <= -1; ++i) star += " " + std::to_string(i);
    write_file(dir / "star_face.obj", star + "\n");
}

void cli_seeds(const fs::path& dir) {
    const char* seeds[][2] = {
        {"bake_builtin", "bake\n--builtin\nbumps\n--size\n16\n--seed\n7\n-o\nout.ktx2"},
        {"bake_batch",
         "bake\na.png\nb.exr\n--out-dir\nout\n--from\nnormal\n--directx\n--bits\n16f\n--json\n"
         "s.json"},
        {"bake_height",
         "bake\nh.pfm\n--from\nheight\n--strength\n2.5\n--bake-roughness\n64\n--wrap\nclamp\n"
         "--bits\n8\n--threads\n2\n--max-size\n4096\n--format\npng\n-o\nh"},
        {"info", "info\nmap.ktx2"},
        {"help", "--help"},
        {"bake_help", "bake\n--help"},
        {"version", "--version"},
        {"bad_bits", "bake\n--builtin\nridges\n--bits\n12"},
        {"equals_form", "bake\n--builtin=checker\n--size=64\n--bits=32f\n-o=x.ktx2"},
    };
    for (const auto& seed : seeds) write_file(dir / (std::string(seed[0]) + ".args"), seed[1]);
}

void preset_seeds(const fs::path& dir) {
    Preset preset;
    write_file(dir / "defaults.json", preset_to_json(preset));
    preset.scene = "sphere";
    preset.bumps.source = "ridges";
    preset.bumps.bits = StoragePolicy::fixed(Storage::Float16);
    preset.shading.fog = FogMode::Exp2;
    preset.shading.fade_distance = FadeDistance::Eye;
    preset.shading.anisotropy = 8;
    preset.shading.msaa = 4;
    preset.techniques = {Technique::Bump, Technique::Fade};
    preset.layout = PaneLayout::Split;
    preset.divider = 0.25f;
    write_file(dir / "split_fog.json", preset_to_json(preset));
    write_file(dir / "minimal.json", "{\"leanfade_preset\": 1, \"shading\": {\"fade\": 0.5}}");
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s CORPUS_FOLDER\n", argv[0]);
        return 2;
    }
    try {
        const fs::path root = argv[1];
        const struct {
            const char* target;
            void (*make)(const fs::path&);
        } sets[] = {{"fuzz_image_bake", image_seeds},
                    {"fuzz_ktx2", ktx2_seeds},
                    {"fuzz_obj", obj_seeds},
                    {"fuzz_cli", cli_seeds},
                    {"fuzz_preset", preset_seeds}};
        for (const auto& set : sets) {
            const fs::path dir = root / set.target;
            fs::create_directories(dir);
            set.make(dir);
            // Every image, KTX2 and OBJ seed must load (a seed that the reader refuses would
            // only teach the fuzzer the first few bytes), but for the few named "refused_",
            // which sit next to a check and must be refused by it.
            for (const auto& entry : fs::directory_iterator(dir)) {
                const std::string path = entry.path().string();
                if (entry.path().filename().string().starts_with("refused_")) {
                    try {
                        if (set.make == image_seeds) io::read_image(path);
                        if (set.make == ktx2_seeds) io::read_ktx2(path);
                    } catch (const Error&) {
                        continue;
                    }
                    throw Error(path, "seed named refused_ was accepted");
                }
                if (set.make == image_seeds) io::read_image(path);
                if (set.make == ktx2_seeds) io::read_ktx2(path);
                if (set.make == obj_seeds) scene::load_obj(path);
                if (set.make == preset_seeds) read_preset(path);
            }
        }
    } catch (const Error& e) {
        std::fprintf(stderr, "leanfade_fuzz_seeds: %s\n", e.what());
        return 1;
    }
    return 0;
}
