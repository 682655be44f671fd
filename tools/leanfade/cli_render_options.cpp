// Command-line binding of the shading settings, the LEAN map source and the GL context.
#include "cli_render_options.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "leanfade/core/error.hpp"
#include "leanfade/core/procedural.hpp"
#include "leanfade/core/text.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::cli {
namespace {

std::string format_vec3(const glm::vec3& v) {
    std::ostringstream out;
    out << v.x << "," << v.y << "," << v.z;
    return out.str();
}

bool parse_float(const std::string& text, float& value) {
    if (text.empty()) return false;
    char* end = nullptr;
    value = std::strtof(text.c_str(), &end);
    return end != nullptr && *end == 0 && std::isfinite(value);
}

// "x,y,z", or a single value repeated when `allow_grey`.
glm::vec3 parse_vec3(const std::string& text, const std::string& flag, bool allow_grey) {
    const std::vector<std::string> parts = split(text, ',');
    glm::vec3 v(0.0f);
    if (parts.size() == 1 && allow_grey && parse_float(parts[0], v.x)) return glm::vec3(v.x);
    if (parts.size() == 3 && parse_float(parts[0], v.x) && parse_float(parts[1], v.y) &&
        parse_float(parts[2], v.z))
        return v;
    throw Error(flag, std::string("expected ") + (allow_grey ? "R,G,B or one value" : "X,Y,Z") +
                          ", got '" + text + "'");
}

Storage parse_storage(const std::string& bits) {
    if (bits == "8") return Storage::Unorm8;
    if (bits == "16") return Storage::Unorm16;
    if (bits == "16f") return Storage::Float16;
    if (bits == "32f") return Storage::Float32;
    throw Error("--bits", "expected 8, 16, 16f or 32f, got '" + bits + "'");
}

bool ends_with(const std::string& s, const std::string& suffix) {
    if (s.size() < suffix.size()) return false;
    for (std::size_t i = 0; i < suffix.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) != suffix[i])
            return false;
    return true;
}

}  // namespace

void add_shading_options(CLI::App& app, ShadingFlags& f) {
    ShadingSettings& s = f.settings;
    const std::string group = "Shading (SPEC §4; colours linear RGB)";
    auto vec = [&](const char* name, std::string& target, const glm::vec3& def, const char* help) {
        const bool colour = std::string(name) != "--light-dir";
        app.add_option(name, target, help)
            ->default_str(format_vec3(def))
            ->type_name(colour ? "R,G,B" : "X,Y,Z")
            ->group(group);
    };
    auto num = [&](const char* name, auto& target, const char* help) {
        return app.add_option(name, target, help)->capture_default_str()->group(group);
    };
    vec("--light-dir", f.light_dir, s.light_direction,
        "Direction toward the light, world space (y up, camera on +z)");
    vec("--light-color", f.light_color, s.light_color, "Light colour (R,G,B or one value)");
    vec("--ambient", f.ambient, s.ambient, "Ambient Ka (R,G,B or one value)");
    vec("--kd", f.kd, s.kd, "Diffuse Kd (R,G,B or one value)");
    vec("--ks", f.ks, s.ks, "Specular Ks (R,G,B or one value)");
    num("--shininess", s.shininess, "Blinn-Phong exponent s (0.001 to 1e7)");
    num("--fresnel-bias", s.fresnel_bias, "Fresnel bias Fb");
    num("--fresnel-scale", s.fresnel_scale, "Fresnel scale Fs");
    num("--fade", s.fade, "Fading rate Fade >= 0, per bounding radius (fading paper eq. 6)");
    num("--pmax", s.pmax, "Largest fading exponent Pmax >= 1");
    num("--fade-exponent", s.fade_exponent, "Power p of (d Fade)^p");
    app.add_option("--fade-distance", f.fade_distance, "Fading distance d: tangent-z | eye")
        ->capture_default_str()
        ->group(group);
    app.add_option("--fog", f.fog, "Fog: none | linear | exp | exp2")
        ->capture_default_str()
        ->group(group);
    vec("--fog-color", f.fog_color, s.fog_color, "Fog colour (R,G,B or one value)");
    num("--fog-start", s.fog_start, "Linear fog start, bounding radii from the eye");
    num("--fog-end", s.fog_end, "Linear fog end, bounding radii from the eye");
    num("--fog-density", s.fog_density, "Exp / exp2 fog density per bounding radius");
    num("--strength", s.bump_strength, "Bump height per texel spacing (on-the-fly height bakes)");
    num("--tiling", s.tiling, "Texture repeats per unit of the mesh's uv");
    num("--mip-bias", s.mip_bias, "Texture LOD bias (negative = sharper)");
    num("--aniso", s.anisotropy, "Anisotropic filtering ratio (1 = trilinear)");
    num("--msaa", s.msaa, "Multisample anti-aliasing samples (1 = off)");
}

ShadingSettings resolve_shading(const ShadingFlags& f) {
    ShadingSettings s = f.settings;
    if (!f.light_dir.empty()) s.light_direction = parse_vec3(f.light_dir, "--light-dir", false);
    if (!f.light_color.empty()) s.light_color = parse_vec3(f.light_color, "--light-color", true);
    if (!f.ambient.empty()) s.ambient = parse_vec3(f.ambient, "--ambient", true);
    if (!f.kd.empty()) s.kd = parse_vec3(f.kd, "--kd", true);
    if (!f.ks.empty()) s.ks = parse_vec3(f.ks, "--ks", true);
    if (!f.fog_color.empty()) s.fog_color = parse_vec3(f.fog_color, "--fog-color", true);
    s.fade_distance = parse_fade_distance(f.fade_distance, "--fade-distance");
    s.fog = parse_fog_mode(f.fog, "--fog");
    validate(s);
    return s;
}

void add_lean_source_options(CLI::App& app, LeanSourceFlags& f) {
    const std::string group = "Bumps";
    std::string names;
    for (const std::string& n : builtin_bump_names()) names += (names.empty() ? "" : ", ") + n;
    app.add_option("--bumps", f.bumps,
                   "Built-in bump set (" + names +
                       "), a height/normal map image, or a .ktx2 LEAN map from `leanfade bake`")
        ->capture_default_str()
        ->group(group);
    app.add_option("--from", f.from,
                   "Image inputs: auto (1-2 channels height, 3-4 normal, as bake), height or "
                   "normal map")
        ->capture_default_str()
        ->group(group);
    app.add_flag("--directx", f.directx, "Normal maps use the DirectX convention (-Y)")
        ->group(group);
    app.add_option("--bits", f.bits, "Storage of on-the-fly bakes: 8, 16, 16f, 32f")
        ->capture_default_str()
        ->group(group);
    app.add_option("--seed", f.seed, "Seed of the built-in bump set")
        ->capture_default_str()
        ->group(group);
    app.add_option("--texture-size", f.texture_size, "Texels per side of a built-in bump set")
        ->capture_default_str()
        ->group(group);
    app.add_option("--max-size", f.max_size,
                   "Largest accepted width or height of a --bumps image or .ktx2 map (refused "
                   "before decoding)")
        ->check(CLI::Range(1, 1 << 20))
        ->capture_default_str()
        ->group(group);
}

PackedLeanMap load_lean_map(const LeanSourceFlags& f, const ShadingSettings& settings) {
    const std::string generator = std::string("leanfade ") + LEANFADE_VERSION;
    if (f.from != "auto" && f.from != "height" && f.from != "normal")
        throw Error("--from", "expected auto, height or normal, got '" + f.from + "'");
    if (f.texture_size < 4 || f.texture_size > kDefaultMaxImageDimension)
        throw Error("--texture-size", "must be in [4, " +
                                          std::to_string(kDefaultMaxImageDimension) + "], got " +
                                          std::to_string(f.texture_size));
    const Storage storage = parse_storage(f.bits);
    io::ReadOptions read_options;
    read_options.max_dimension = f.max_size;
    if (ends_with(f.bumps, ".ktx2")) return io::read_ktx2(f.bumps, read_options);

    BakeOptions options;
    options.strength = settings.bump_strength;
    options.convention = f.directx ? NormalConvention::DirectX : NormalConvention::OpenGL;
    // The fused fast path of `leanfade bake` (the same bytes as bake_lean_map + pack_lean_map).
    const auto& builtins = builtin_bump_names();
    if (std::find(builtins.begin(), builtins.end(), f.bumps) != builtins.end()) {
        return bake_packed(make_builtin_height(f.bumps, f.texture_size, f.seed), BakeSource::Height,
                           options, storage, generator, f.bumps)
            .packed;
    }
    const Image image = io::read_image(f.bumps, read_options);
    const BakeSource source = f.from == "height"   ? BakeSource::Height
                              : f.from == "normal" ? BakeSource::Normal
                                                   : BakeSource::Auto;
    return bake_packed(image, source, options, storage, generator, f.bumps).packed;
}

gl::ContextOptions context_options(const GlFlags& flags) {
    gl::ContextOptions options;
    options.device = flags.egl_device;
    return options;
}

gl::ShaderSources shader_sources(const GlFlags& flags) {
    return flags.shader_dir.empty() ? gl::ShaderSources::embedded()
                                    : gl::ShaderSources::directory(flags.shader_dir);
}

void add_camera_options(CLI::App& app, float& fov, std::string& view_dir, const char* view_from,
                        std::string* target) {
    app.add_option("--fov", fov, "Vertical field of view in degrees")->capture_default_str();
    app.add_option("--view-dir", view_dir,
                   std::string("Direction from ") + view_from +
                       " toward the eye, world space (y up)")
        ->capture_default_str();
    if (target != nullptr) {
        app.add_option("--target", *target,
                       "Point the camera looks at, world units (bounding radii; 0 = the centre)")
            ->capture_default_str();
    }
}

void add_reference_samples_option(CLI::App& app, int& ref_samples) {
    app.add_option("--ref-samples", ref_samples,
                   "Reference: k x k samples per pixel at LOD 0 (SPEC §7)")
        ->capture_default_str();
}

void add_gl_options(CLI::App& app, GlFlags& f) {
    const std::string group = "OpenGL";
    app.add_option("--shader-dir", f.shader_dir,
                   "Read the shaders from this folder instead of the built-in copies")
        ->group(group);
    app.add_option("--egl-device", f.egl_device,
                   "EGL device index (default: LEANFADE_EGL_DEVICE, else automatic)")
        ->group(group);
}

std::vector<float> parse_distances(const std::string& text, const std::string& flag) {
    std::vector<float> result;
    for (const std::string& part : split(text, ',')) {
        float d = 0.0f;
        if (!parse_float(part, d))
            throw Error(flag, "expected comma-separated numbers, got '" + text + "'");
        if (!(d > 1.0f))
            throw Error(flag,
                        "distances are in bounding radii from the object's centre and must "
                        "be > 1, got " +
                            part);
        result.push_back(d);
    }
    return result;
}

std::pair<int, int> parse_size(const std::string& text, const std::string& flag) {
    const std::size_t x = text.find('x');
    auto parse_int = [&](const std::string& s, int& v) {
        if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos)
            return false;
        v = std::stoi(s);
        return true;
    };
    int w = 0, h = 0;
    if (x == std::string::npos || !parse_int(text.substr(0, x), w) ||
        !parse_int(text.substr(x + 1), h))
        throw Error(flag, "expected WIDTHxHEIGHT in pixels, got '" + text + "'");
    if (w < 16 || h < 16 || w > 8192 || h > 8192)
        throw Error(flag, "each side must be in [16, 8192] pixels, got '" + text + "'");
    return {w, h};
}

}  // namespace leanfade::cli
