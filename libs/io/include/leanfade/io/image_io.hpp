#pragma once
// Image files: PNG, OpenEXR and PFM in, PNG / PFM / OpenEXR out.
//
// Conventions for every function here:
// - Rows are top row first in memory (row 0 = the top of the picture), as in PNG and EXR files;
//   PFM's bottom-first rows are reversed on read and on write.
// - No colour-space conversion anywhere: values are returned and written as stored. PNG samples
//   map linearly to [0,1] (v / 255 or v / 65535) with no sRGB decode, because normal and height
//   maps are data; a caller that wants sRGB output encodes before write_png.
// - Channels are interleaved (1 = gray, 2 = gray + alpha, 3 = RGB, 4 = RGBA).
// - Every failure throws leanfade::Error(file, cause); nothing is printed, nothing exits.
// - Writers go through AtomicFile: the output appears complete or not at all, and an existing
//   file is replaced atomically.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "leanfade/core/image.hpp"
#include "leanfade/io/detail/atomic_file.hpp"

namespace leanfade::io {

// How writers write. Every writer replaces its output atomically (AtomicFile).
// KTX2 supercompression of a LEAN map file's level data (docs/ktx2.md, "Supercompression"):
// none, or Zstandard (KTX2 scheme 2: each level one Zstandard frame with its checksum). What a
// GPU receives is the same either way.
enum class Supercompression { None, Zstandard };
// The settings' names of the supercompressions ("zstd", "none").
const std::vector<std::pair<std::string, Supercompression>>& supercompression_names();
// "zstd" or "none".
const char* to_string(Supercompression supercompression);

struct WriteOptions {
    Durability durability = Durability::Rename;  // Flush: fsync before the rename
    int threads = 0;                             // for copying large outputs; <= 0: all cores
    // LEAN map KTX2 files only (write_ktx2, Ktx2Writer, Ktx2FileSink, write_ktx2_to_memory):
    // other outputs ignore it (`leanfade bake --supercompression`).
    Supercompression supercompression = Supercompression::None;
    int zstd_level = 3;  // Zstandard's level, 1 (fastest) to 19 (smallest)
};

struct ReadOptions {
    // Largest accepted width or height, checked on the header before any pixel memory is
    // allocated (decompression-bomb guard).
    int max_dimension = kDefaultMaxImageDimension;
    // RGBA -> RGB (and a colour PNG's transparency ignored), for callers that never use a colour
    // image's alpha (the bake of normal maps: less memory). Gray + alpha stays as it is.
    bool drop_alpha = false;
};

// Reads a PNG, OpenEXR or PFM image, recognised by its magic bytes (never by its extension).
// - PNG: 8 or 16 bits (1/2/4-bit gray expanded to 8), gray, gray + alpha, RGB, RGBA, palette
//   (expanded to RGB, or RGBA with a tRNS chunk); values in [0,1] as stored (no gamma or sRGB).
// - OpenEXR: scan-line or tiled (level 0), half / float / uint channels, 1-4 channels (R, G, B, A
//   in that order, Y, or Y + A; more channels only if R, G, B, A select 1-4 of them); values as
//   stored (linear), NaN or infinity refused.
// - PFM: "PF" (RGB) or "Pf" (gray), either endianness; values as stored, NaN or infinity refused.
// Bounds (docs/robustness.md): width and height are checked against options.max_dimension on
// the header, before any pixel memory is allocated; a PNG is also refused before decoding when
// its IDAT data is too short to hold the declared pixels (deflate expands at most 1032 times).
// The input file is opened read-only (never waiting on a FIFO) and never modified.
Image read_image(const std::string& path, const ReadOptions& options = {});

// read_image, keeping the integer samples of 8- and 16-bit PNGs (a UnormImage: half the memory
// of the float Image, for baking large maps; UnormImage::to_float() gives read_image's result).
// OpenEXR and PFM files come as floats. Same checks and messages as read_image.
std::variant<Image, UnormImage> read_image_compact(const std::string& path,
                                                   const ReadOptions& options = {});

// read_image_compact on a file's bytes already in memory (for the fuzz targets).
std::variant<Image, UnormImage> read_image_compact_from_memory(const std::vector<std::uint8_t>& bytes,
                                                               const std::string& name,
                                                               const ReadOptions& options = {});

// read_image on a file's bytes already in memory (same formats, checks and messages); `name` is
// the file name the errors give. For callers that hold the data, and for the fuzz targets.
Image read_image_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& name,
                             const ReadOptions& options = {});

// A MIP chain stored one file per level, as Filament's roughness-prefilter writes it:
// `first_level` is NAME_0.EXT, the others NAME_1.EXT, NAME_2.EXT, ... in the same folder, each
// read by read_image (the same checks), sizes halving with floor down to 1 x 1, all of one
// channel count. Throws leanfade::Error naming the file for another name, a missing level or a
// level of another size.
std::vector<Image> read_mip_series(const std::string& first_level, const ReadOptions& options = {});
// The files of the MIP series whose level 0 is `first_level` that exist (NAME_0.EXT, NAME_1.EXT,
// ... up to the first missing one, at most 33): inputs of the run that reads it. Never throws;
// reads nothing.
std::vector<std::string> mip_series_files(const std::string& first_level);

// Writes an 8- or 16-bit PNG of 1-4 channels. Values are clamped to [0,1] and quantised with
// rounding (v * 255 or v * 65535); they are written as-is, with no colour-space conversion. NaN
// is refused.
void write_png(const std::string& path, const Image& image, int bits,
               const WriteOptions& options = {});

// An 8-bit RGBA PNG of `image`'s bytes as they are (what write_png writes for the same values).
void write_png_rgba8(const std::string& path, const Rgba8Image& image,
                     const WriteOptions& options = {});
// The bytes write_png_rgba8 writes; `name` names the image in errors.
std::vector<std::uint8_t> encode_png_rgba8(const Rgba8Image& image, const std::string& name);

// Writes a little-endian PFM of linear float values: 1 channel -> "Pf"; 3 channels -> "PF";
// 2 channels -> "PF" with blue 0; 4 channels -> "PF", alpha dropped. NaN/infinity are refused.
void write_pfm(const std::string& path, const Image& image);

// Writes a 32-bit float OpenEXR (ZIP compressed) of linear values: 1 channel "Y", 2 channels
// "Y" + "A", 3 channels "R", "G", "B", 4 channels "R", "G", "B", "A". NaN/infinity are refused.
void write_exr(const std::string& path, const Image& image);

// Returns a copy with the rows in reverse order (top-first <-> bottom-first, e.g. for a
// glTexImage2D upload, whose first row is the bottom, v = 0).
Image flip(const Image& image);

// Reverses, in place, the order of the rows of a tightly packed buffer of `row_bytes` per row
// (e.g. one layer of a PackedLevel, width * bytes_per_texel bytes per row).
void flip_rows(std::vector<std::uint8_t>& bytes, std::size_t row_bytes);

}  // namespace leanfade::io
