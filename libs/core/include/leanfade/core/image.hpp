#pragma once
// Float images of 1-4 interleaved channels, any size (non-square, non-power-of-two, 1x1).
// Row-major, row 0 is the top row as stored in files; texel (x, y) has u = (x + 0.5) / width and
// v = 1 - (y + 0.5) / height in OpenGL texture space (see io::flip when uploading).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace leanfade {

struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<float> pixels;  // width * height * channels floats

    Image() = default;
    Image(int w, int h, int c, float fill = 0.0f);

    bool empty() const { return width == 0 || height == 0 || channels == 0; }
    std::size_t texel_count() const { return std::size_t(width) * std::size_t(height); }
    std::size_t index(int x, int y, int c = 0) const {
        return (std::size_t(y) * std::size_t(width) + std::size_t(x)) * std::size_t(channels) +
               std::size_t(c);
    }
    float& at(int x, int y, int c = 0) { return pixels[index(x, y, c)]; }
    float at(int x, int y, int c = 0) const { return pixels[index(x, y, c)]; }
    float* row(int y) { return pixels.data() + index(0, y); }
    const float* row(int y) const { return pixels.data() + index(0, y); }
};

// 8-bit RGBA texels, rows top first: width * height * 4 bytes (a texture level for engines).
struct Rgba8Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> texels;
};

// Integer samples as stored in 8- and 16-bit image files (PNG), interleaved and row-major like
// Image; a sample's value is float(sample) / float(max_value) in [0, 1], exactly the float that
// Image holds for it after io::read_image. Half the memory of the float Image, for the bake of
// large 8- and 16-bit maps (bake_packed_to converts rows as it reads them).
struct UnormImage {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::uint16_t max_value = 65535;     // 255 for 8-bit samples
    std::vector<std::uint16_t> samples;  // width * height * channels

    UnormImage() = default;
    UnormImage(int w, int h, int c, std::uint16_t max);  // samples zero

    std::size_t texel_count() const { return std::size_t(width) * std::size_t(height); }
    const std::uint16_t* row(int y) const {
        return samples.data() + std::size_t(y) * std::size_t(width) * std::size_t(channels);
    }
    std::uint16_t* row(int y) {
        return samples.data() + std::size_t(y) * std::size_t(width) * std::size_t(channels);
    }
    // The float image of the same values (what io::read_image returns for the file).
    Image to_float() const;
    // The largest code of the samples' own precision: max_value divided by the greatest common
    // divisor of the samples of the first `channels_used` channels (all when 0) and max_value.
    // A 16-bit file of 8-bit data (every sample a multiple of 257) gives 255; 0 for no samples.
    int effective_max_code(int channels_used = 0) const;
};

// `image` resampled to width x height (bilinear, the image repeating, texel centres aligned):
// a texture of another size than the map it goes with (a metallic-roughness texture beside a
// normal map). The image itself when it has that size already.
Image resampled(const Image& image, int width, int height);

// Largest accepted width or height for any image read or baked unless raised explicitly
// (a guard against decompression bombs and absurd headers).
inline constexpr int kDefaultMaxImageDimension = 16384;

}  // namespace leanfade
