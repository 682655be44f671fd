#pragma once
// PNG files with text chunks, and LEAN maps as a pair of PNG files.
//
// `leanfade bake --format png` writes the top level of a LEAN map as two RGBA PNGs, NAME.lean1.png
// and NAME.lean2.png (docs/math.md §3 layout, 8 or 16 bits as the storage), and its plateau layer
// (docs/math.md §10), when it has one, as a third, NAME.plateau.png; each carries sc and the
// bake's metadata in tEXt chunks with the keys of the KTX2 file (docs/ktx2.md). The files load
// back (`--bumps NAME.lean1.png`): the MIP chains are rebuilt from the top level with the bake's
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

// The file names of a pair: NAME.lean1.png and NAME.lean2.png, and of the plateau layer,
// NAME.plateau.png.
inline constexpr const char* kLeanPngSuffixes[2] = {".lean1.png", ".lean2.png"};
inline constexpr const char* kPlateauPngSuffix = ".plateau.png";
// NAME for a path ending in .lean1.png, .lean2.png or .plateau.png (in any case), "" for any
// other path.
std::string lean_png_pair_base(const std::string& path);

// Writes the top level of `packed` (Unorm8 or Unorm16 storage: 8- or 16-bit PNGs; float storages
// are refused) to lean1_path and lean2_path, and its plateau layer, when it has one, to
// plateau_path (which must then be given), each with the metadata.
void write_lean_png_pair(const std::string& lean1_path, const std::string& lean2_path,
                         const PackedLeanMap& packed, const WriteOptions& options = {},
                         const std::string& plateau_path = {});

// Reads the pair named by any of its files: both must be RGBA PNGs of the same size and bit
// depth with the metadata of write_lean_png_pair and the same sc. The MIP chain is rebuilt from
// the top level (build_mip_chain, the bake's filter) and packed to the files' storage. A pair
// whose layout names the plateau layer needs NAME.plateau.png too (same size, depth and sc), whose
// stored values are filtered alike; a pair without it loads without a plateau layer.
PackedLeanMap read_lean_png_pair(const std::string& path, const ReadOptions& options = {});

}  // namespace leanfade::io
