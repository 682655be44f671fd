#pragma once
// LEAN maps generated on the GPU (the LEAN paper's "per-frame generation", §5): a compute pass
// (shaders/generate_lean.comp) writes the top level of both slices from a height or normal
// texture, exactly as the CPU baker computes its top level (docs/math.md §2-3), then
// glGenerateMipmap builds the other levels by averaging the packed values (correct because the
// packing is affine per channel, docs/math.md §3; for power-of-two sizes the 2 x 2 box equals the
// CPU's area filter, up to the re-quantisation of each level).
//
// The texture has the layout Renderer::set_lean_map uploads: a GL_TEXTURE_2D_ARRAY of two slices
// (lean1, lean2) with every MIP level, texel row 0 at v = 0 (the bottom row of an image file).
#include <string>
#include <vector>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/detail/objects.hpp"
#include "leanfade/gl/shader_library.hpp"
#include "leanfade/gl/detail/timer.hpp"

namespace leanfade::gl {

enum class GenerateInput {
    Height,  // first channel: heights in texel units (docs/math.md §2, Sobel / 8)
    Normal,  // channels 0-2: a tangent-space normal map encoded 0.5 n + 0.5
    // A layered material's bump layers mixed by the "height" method at one instant
    // (docs/math.md §6): the caller binds them as for drawing (set_layer_source).
    Layers,
};

struct GenerateOptions {
    float strength = 1.0f;     // height per texel spacing (height maps)
    Wrap wrap = Wrap::Repeat;  // Sobel taps past the edge (height maps)
    NormalConvention convention = NormalConvention::OpenGL;  // normal maps
    float scale = 1.0f;                     // sc the slices are packed with (docs/math.md §3), > 0
    float bake_roughness_shininess = 0.0f;  // s > 0: 1/s added to Mxx, Myy (LEAN eq. 6)
    Storage storage = Storage::Unorm16;     // texel format of both slices
    // Two-lobe LEAN's plateau layer (docs/math.md §10) of the generated map, with this epsilon
    // (slope units; 0 = none): a second pass (shaders/generate_plateau.comp) from the generated
    // top level, as plateau_texels of leanfade/core/detail/plateau.hpp.
    float plateau_epsilon = kDefaultPlateauEpsilon;
};

class LeanGenerator {
  public:
    // The context must stay alive and current while the generator is used.
    explicit LeanGenerator(Context& context, ShaderSources sources = ShaderSources::embedded());
    LeanGenerator(const LeanGenerator&) = delete;
    LeanGenerator& operator=(const LeanGenerator&) = delete;

    // Uploads the source as a float texture, rows flipped so that +v is up. Heights: the first
    // channel (R32F); normals: channels 0-2 (RGB32F), at least 3 channels. Throws
    // leanfade::Error("generate", cause) for an empty image, too few channels or a size above
    // GL_MAX_TEXTURE_SIZE.
    void set_source(const Image& image, GenerateInput input);

    // The "height" method's per-frame source: the mixed slopes sum t_i k_i B_i(uv tiling_i +
    // offset_i) of a layered material at the texel centres of a width x height map over the
    // surface's uv square (mix_slopes_at of leanfade/core/detail/layers.hpp computes the same on the
    // CPU). The layers are read from what is bound when write_top_level runs: their LEAN maps at
    // units LF_BINDING_LAYER_MAPS + i, the weight map at LF_BINDING_LAYER_WEIGHTS and an
    // LfLayerUniforms block at LF_BINDING_LAYER_BLOCK (shaders/bindings.glsl), as the renderer
    // binds them for drawing. Strength, wrap and convention of GenerateOptions do not apply.
    // Throws leanfade::Error("generate", cause) for a size outside [1, GL_MAX_TEXTURE_SIZE].
    void set_layer_source(int width, int height);

    // The compute pass: level 0 of both slices, and of the plateau texture with
    // options.plateau_epsilon > 0. (Re)allocates the textures, with every MIP level, when the
    // source size or the storage changed. Throws leanfade::Error("generate", cause) without a
    // source, for sc <= 0 or a non-finite or negative option.
    void write_top_level(const GenerateOptions& options);
    // glGenerateTextureMipmap: levels 1.. from level 0, of both textures.
    void generate_mipmaps();
    // Both of the above.
    void generate(const GenerateOptions& options);

    // The generated texture (0 before the first write_top_level).
    GLuint texture() const { return texture_.get(); }
    // The generated plateau layer: a GL_TEXTURE_2D, RGBA16F, every MIP level, texel
    // (f, f Bs.x, f Bs.y, f |Bs|^2) as MapKind::Plateau holds it; 0 when the last
    // write_top_level had plateau_epsilon 0.
    GLuint plateau_texture() const { return plateau_epsilon_ > 0.0f ? plateau_.get() : 0; }
    int width() const { return width_; }
    int height() const { return height_; }
    int levels() const { return levels_; }

    // Every level read back in the CPU baker's layout (rows top first), with sc, storage and the
    // baked-roughness flag of the last pass; generator "leanfade GPU". Waits for the GPU.
    PackedLeanMap read_back() const;
    // Every level of the plateau texture read back as floats, rows top first (empty when there
    // is none). Waits for the GPU.
    std::vector<Image> read_back_plateau() const;

  private:
    GLuint program(Storage storage);
    void write_plateau_top_level();

    Context& context_;
    ShaderSources sources_;
    GenerateInput input_ = GenerateInput::Height;
    Texture source_;
    Texture texture_;
    Program programs_[3][4];  // [input][storage], built on first use
    Texture plateau_;
    Program plateau_program_;
    float plateau_epsilon_ = 0.0f;
    int width_ = 0, height_ = 0, levels_ = 0;
    Storage storage_ = Storage::Unorm16;
    float scale_ = 1.0f;
    float baked_shininess_ = 0.0f;
    NormalConvention convention_ = NormalConvention::OpenGL;
};

// Frame times of per-frame generation: after `warmup` untimed generations, `frames` timed ones,
// the compute pass and the MIP generation timed as separate intervals of `timer` (milliseconds,
// one value per frame each).
struct GenerationTimes {
    std::vector<double> pass_ms;
    std::vector<double> mipmap_ms;
};
GenerationTimes time_generation(LeanGenerator& generator, const GenerateOptions& options,
                                int frames, int warmup, IntervalTimer& timer);

}  // namespace leanfade::gl
