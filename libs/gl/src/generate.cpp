// LEAN map generation on the GPU: compute pass for the top level, glGenerateMipmap for the rest.
#include "leanfade/gl/detail/generate.hpp"

#include "leanfade/core/detail/plateau.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "leanfade/core/error.hpp"

namespace leanfade::gl {
namespace {

constexpr int kGroupSize = 8;  // local_size_x and _y of generate_lean.comp

struct SliceFormat {
    GLenum internal_format;
    GLenum type;
    const char* qualifier;
};

SliceFormat slice_format(Storage storage) {
    switch (storage) {
        case Storage::Unorm8:
            return {GL_RGBA8, GL_UNSIGNED_BYTE, "rgba8"};
        case Storage::Unorm16:
            return {GL_RGBA16, GL_UNSIGNED_SHORT, "rgba16"};
        case Storage::Float16:
            return {GL_RGBA16F, GL_HALF_FLOAT, "rgba16f"};
        case Storage::Float32:
            return {GL_RGBA32F, GL_FLOAT, "rgba32f"};
    }
    return {GL_RGBA16, GL_UNSIGNED_SHORT, "rgba16"};
}

GLint location(GLuint program, const char* name) {
    return glGetUniformLocation(program, name);
}

}  // namespace

LeanGenerator::LeanGenerator(Context& context, ShaderSources sources)
    : context_(context), sources_(std::move(sources)) {}

GLuint LeanGenerator::program(Storage storage) {
    Program& p = programs_[int(input_)][int(storage)];
    if (!p) {
        const std::string source = input_ == GenerateInput::Height   ? "SOURCE_HEIGHT"
                                   : input_ == GenerateInput::Normal ? "SOURCE_NORMAL"
                                                                     : "SOURCE_LAYERS";
        p = build_compute_program(
            sources_, "generate_lean.comp",
            {source, std::string("SLICE_FORMAT ") + slice_format(storage).qualifier});
    }
    return p.get();
}

void LeanGenerator::set_layer_source(int width, int height) {
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (width < 1 || height < 1 || width > max_size || height > max_size)
        throw Error("generate", "the mixed map's size must be in [1, " +
                                    std::to_string(max_size) + "] (GL_MAX_TEXTURE_SIZE)");
    source_.reset();
    input_ = GenerateInput::Layers;
    if (width != width_ || height != height_) texture_.reset();
    width_ = width;
    height_ = height;
}

void LeanGenerator::set_source(const Image& image, GenerateInput input) {
    if (input == GenerateInput::Layers)
        throw Error("generate", "layers are a source of set_layer_source, not an image");
    if (image.empty() || image.width < 1 || image.height < 1)
        throw Error("generate", "the source image is empty");
    if (input == GenerateInput::Normal && image.channels < 3)
        throw Error("generate", "a normal map needs 3 or 4 channels, this image has " +
                                    std::to_string(image.channels));
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (image.width > max_size || image.height > max_size)
        throw Error("generate", "the source is larger than GL_MAX_TEXTURE_SIZE (" +
                                    std::to_string(max_size) + ")");
    const int channels = input == GenerateInput::Height ? 1 : 3;
    // Rows bottom first, only the channels used.
    std::vector<float> texels(std::size_t(image.width) * std::size_t(image.height) *
                              std::size_t(channels));
    for (int y = 0; y < image.height; ++y) {
        const float* src = image.row(image.height - 1 - y);
        float* dst = &texels[std::size_t(y) * std::size_t(image.width) * std::size_t(channels)];
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < channels; ++c) dst[x * channels + c] = src[x * image.channels + c];
    }
    Texture texture = create_texture(GL_TEXTURE_2D);
    glTextureStorage2D(texture.get(), 1, channels == 1 ? GL_R32F : GL_RGB32F, image.width,
                       image.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(texture.get(), 0, 0, 0, image.width, image.height,
                        channels == 1 ? GL_RED : GL_RGB, GL_FLOAT, texels.data());
    glTextureParameteri(texture.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    context_.check("uploading the generator's source");
    source_ = std::move(texture);
    input_ = input;
    if (image.width != width_ || image.height != height_) texture_.reset();
    width_ = image.width;
    height_ = image.height;
}

void LeanGenerator::write_top_level(const GenerateOptions& options) {
    if (!source_ && input_ != GenerateInput::Layers)
        throw Error("generate", "no source image was set");
    if (!(options.scale > 0.0f) || !std::isfinite(options.scale))
        throw Error("generate", "sc must be a finite number > 0");
    if (!std::isfinite(options.strength) || !std::isfinite(options.bake_roughness_shininess) ||
        options.bake_roughness_shininess < 0.0f)
        throw Error("generate", "strength and the baked shininess must be finite (shininess >= 0)");
    if (!std::isfinite(options.plateau_epsilon) || options.plateau_epsilon < 0.0f)
        throw Error("generate", "the plateau epsilon must be finite and >= 0");
    const SliceFormat format = slice_format(options.storage);
    if (!texture_ || options.storage != storage_) {
        levels_ = mip_level_count(width_, height_);
        Texture texture = create_texture(GL_TEXTURE_2D_ARRAY);
        glTextureStorage3D(texture.get(), levels_, format.internal_format, width_, height_, 2);
        set_repeat_trilinear(texture.get(), levels_);
        texture_ = std::move(texture);
        storage_ = options.storage;
        plateau_.reset();
    }
    const GLuint p = program(options.storage);
    const float inv_s =
        options.bake_roughness_shininess > 0.0f ? 1.0f / options.bake_roughness_shininess : 0.0f;
    glProgramUniform1f(p, location(p, "u_strength"), options.strength);
    glProgramUniform1f(p, location(p, "u_scale"), options.scale);
    glProgramUniform1f(p, location(p, "u_inv_s"), inv_s);
    glProgramUniform1f(p, location(p, "u_green_sign"),
                       options.convention == NormalConvention::DirectX ? -1.0f : 1.0f);
    glProgramUniform1i(p, location(p, "u_wrap_repeat"), options.wrap == Wrap::Repeat ? 1 : 0);
    glProgramUniform1f(p, location(p, "u_min_normal_z"), kMinNormalZ);
    glProgramUniform1f(p, location(p, "u_lean_offset"),
                       lean_offset(default_encoding(options.storage)));
    glUseProgram(p);
    if (input_ != GenerateInput::Layers) glBindTextureUnit(0, source_.get());
    glBindImageTexture(0, texture_.get(), 0, GL_TRUE, 0, GL_WRITE_ONLY, format.internal_format);
    glDispatchCompute(GLuint((width_ + kGroupSize - 1) / kGroupSize),
                      GLuint((height_ + kGroupSize - 1) / kGroupSize), 1);
    // The next reads are texture fetches (the renderer, mipmap generation) and read-backs.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                    GL_FRAMEBUFFER_BARRIER_BIT);
    glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, format.internal_format);
    glUseProgram(0);
    scale_ = options.scale;
    baked_shininess_ = inv_s > 0.0f ? options.bake_roughness_shininess : 0.0f;
    convention_ = options.convention;
    plateau_epsilon_ = options.plateau_epsilon;
    if (plateau_epsilon_ > 0.0f) write_plateau_top_level();
}

void LeanGenerator::write_plateau_top_level() {
    if (!plateau_) {
        Texture texture = create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(texture.get(), levels_, GL_RGBA16F, width_, height_);
        set_repeat_trilinear(texture.get(), levels_);
        plateau_ = std::move(texture);
    }
    if (!plateau_program_)
        plateau_program_ = build_compute_program(sources_, "generate_plateau.comp", {});
    const GLuint p = plateau_program_.get();
    glProgramUniform1f(p, location(p, "u_scale"), scale_);
    // The rule of plateau.hpp for this size; a generated map's slopes are continuous (no
    // quantisation step).
    const PlateauRule rule = plateau_rule(width_, height_, plateau_epsilon_);
    glProgramUniform1f(p, location(p, "u_epsilon"), rule.epsilon);
    glProgramUniform2i(p, location(p, "u_radius"), rule.radius_x, rule.radius_y);
    glUseProgram(p);
    glBindTextureUnit(0, texture_.get());
    glBindImageTexture(0, plateau_.get(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glDispatchCompute(GLuint((width_ + kGroupSize - 1) / kGroupSize),
                      GLuint((height_ + kGroupSize - 1) / kGroupSize), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                    GL_FRAMEBUFFER_BARRIER_BIT);
    glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glBindTextureUnit(0, 0);
    glUseProgram(0);
}

void LeanGenerator::generate_mipmaps() {
    if (!texture_) throw Error("generate", "no top level was written");
    if (levels_ > 1) glGenerateTextureMipmap(texture_.get());
    if (levels_ > 1 && plateau_texture() != 0) glGenerateTextureMipmap(plateau_.get());
}

void LeanGenerator::generate(const GenerateOptions& options) {
    write_top_level(options);
    generate_mipmaps();
}

PackedLeanMap LeanGenerator::read_back() const {
    if (!texture_) throw Error("generate", "no top level was written");
    PackedLeanMap map;
    map.storage = storage_;
    map.encoding = default_encoding(storage_);
    map.scale = scale_;
    map.roughness_baked = baked_shininess_ > 0.0f;
    map.baked_shininess = baked_shininess_;
    map.source_convention = convention_;
    map.generator = "leanfade GPU";
    const SliceFormat format = slice_format(storage_);
    const std::size_t texel_bytes = std::size_t(bytes_per_texel(storage_));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    int w = width_, h = height_;
    for (int level = 0; level < levels_; ++level) {
        const std::size_t row_bytes = std::size_t(w) * texel_bytes;
        const std::size_t slice_bytes = row_bytes * std::size_t(h);
        std::vector<std::uint8_t> bytes(2 * slice_bytes);
        glGetTextureImage(texture_.get(), level, GL_RGBA, format.type, GLsizei(bytes.size()),
                          bytes.data());
        PackedLevel out;
        out.width = w;
        out.height = h;
        out.lean1.resize(slice_bytes);
        out.lean2.resize(slice_bytes);
        for (int y = 0; y < h; ++y) {
            const std::size_t src = std::size_t(h - 1 - y) * row_bytes;
            const std::size_t dst = std::size_t(y) * row_bytes;
            std::memcpy(&out.lean1[dst], &bytes[src], row_bytes);
            std::memcpy(&out.lean2[dst], &bytes[slice_bytes + src], row_bytes);
        }
        map.levels.push_back(std::move(out));
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    return map;
}

std::vector<Image> LeanGenerator::read_back_plateau() const {
    std::vector<Image> chain;
    if (plateau_texture() == 0) return chain;
    int w = width_, h = height_;
    for (int level = 0; level < levels_; ++level) {
        std::vector<float> rows(std::size_t(w) * std::size_t(h) * 4);
        glGetTextureImage(plateau_.get(), level, GL_RGBA, GL_FLOAT,
                          GLsizei(rows.size() * sizeof(float)), rows.data());
        Image out(w, h, 4);
        for (int y = 0; y < h; ++y)  // GL's row 0 is the bottom row
            std::memcpy(out.row(y), &rows[std::size_t(h - 1 - y) * std::size_t(w) * 4],
                        std::size_t(w) * 4 * sizeof(float));
        chain.push_back(std::move(out));
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
    return chain;
}

GenerationTimes time_generation(LeanGenerator& generator, const GenerateOptions& options,
                                int frames, int warmup, IntervalTimer& timer) {
    if (frames < 1) throw Error::setting("frames", "must be at least 1");
    for (int i = 0; i < warmup; ++i) generator.generate(options);
    GenerationTimes times;
    for (int i = 0; i < frames; ++i) {
        timer.begin();
        generator.write_top_level(options);
        timer.end();
        timer.begin();
        generator.generate_mipmaps();
        timer.end();
        const std::vector<double> ms = timer.collect();
        times.pass_ms.push_back(ms.at(0));
        times.mipmap_ms.push_back(ms.at(1));
    }
    return times;
}

}  // namespace leanfade::gl
