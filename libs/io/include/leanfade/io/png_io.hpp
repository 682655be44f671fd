#pragma once
// PNG files with text chunks, and LEAN maps as a pair of PNG files.
//
// `leanfade bake --format png` writes the top level of a LEAN map as two RGBA PNGs, NAME.lean1.png
// and NAME.lean2.png (docs/math.md §3 layout, 8 or 16 bits as the storage), each carrying sc and
// the bake's metadata in tEXt chunks with the keys of the KTX2 file (docs/ktx2.md). The pair loads
// back (`--bumps NAME.lean1.png`): the MIP chain is rebuilt from the top level with the bake's
// filter. Every failure throws leanfade::Error(file, cause).
#include <string>
#include <vector>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::io {

// One tEXt chunk: a keyword of 1-79 Latin-1 characters and its text.
struct PngText {
    std::string key;
    std::string value;
};

// write_png with text chunks, written before the image data.
void write_png_with_text(const std::string& path, const Image& image, int bits,
                         const std::vector<PngText>& text, const WriteOptions& options = {});

// A PNG's samples as stored (8 or 16 bits: UnormImage::max_value 255 or 65535) and its text
// chunks (those before the image data), with read_image's checks and messages.
UnormImage read_png_with_text(const std::string& path, std::vector<PngText>& text,
                              const ReadOptions& options = {});

// The file names of a pair: NAME.lean1.png and NAME.lean2.png.
inline constexpr const char* kLeanPngSuffixes[2] = {".lean1.png", ".lean2.png"};
// NAME for a path ending in .lean1.png or .lean2.png (in any case), "" for any other path.
std::string lean_png_pair_base(const std::string& path);

// Writes the top level of `packed` (Unorm8 or Unorm16 storage: 8- or 16-bit PNGs; float storages
// are refused) to lean1_path and lean2_path, each with the metadata.
void write_lean_png_pair(const std::string& lean1_path, const std::string& lean2_path,
                         const PackedLeanMap& packed, const WriteOptions& options = {});

// Reads the pair named by either of its files: both must be RGBA PNGs of the same size and bit
// depth with the metadata of write_lean_png_pair and the same sc. The MIP chain is rebuilt from
// the top level (build_mip_chain, the bake's filter) and packed to the files' storage.
PackedLeanMap read_lean_png_pair(const std::string& path, const ReadOptions& options = {});

}  // namespace leanfade::io
