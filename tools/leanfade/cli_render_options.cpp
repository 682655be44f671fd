// Command-line binding of the shading settings, the LEAN map source and the GL context.
#include "cli_render_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "cli_flags.hpp"
#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/detail/parameters.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/eval/results.hpp"
#include "leanfade/io/detail/png_io.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/version.hpp"

namespace leanfade::cli {
namespace {

// "<help> (<unit>; <range>; <equation>)" from a schema row.
std::string parameter_help(const ParameterInfo& row) {
    std::string notes(row.unit);
    auto add = [&](const std::string& note) {
        if (!note.empty()) notes += (notes.empty() ? "" : "; ") + note;
    };
    const auto number = [](float v) {
        std::ostringstream out;
        out << v;
        return out.str();
    };
    if (row.kind == ParameterKind::Scalar || row.kind == ParameterKind::Integer) {
        const bool lower = std::isfinite(row.min), upper = std::isfinite(row.max);
        if (lower && upper)
            add(std::string(row.min_exclusive ? "(" : "[") + number(row.min) + ", " +
                number(row.max) + "]");
        else if (lower)
            add(std::string(row.min_exclusive ? "> " : ">= ") + number(row.min));
    }
    if (row.kind == ParameterKind::Choice) {
        std::string names;
        for (std::string_view c : row.choices)
            names += (names.empty() ? "" : " | ") + std::string(c);
        add(names);
    }
    add(std::string(row.equation));
    return std::string(row.help) + (notes.empty() ? "" : " (" + notes + ")");
}

}  // namespace

void add_shading_options(CLI::App& app, ShadingFlags& f) {
    const std::string group = "Shading (docs/math.md §4; colours linear RGB)";
    const ShadingSettings defaults = f.settings;
    for (const ParameterInfo& row : shading_parameters()) {
        const std::string flag = flag_for_setting(row.key);
        const std::string help = parameter_help(row);
        CLI::Option* option = nullptr;
        switch (row.kind) {
            case ParameterKind::Scalar:
                option = app.add_option(flag, f.settings.*row.scalar, help)->capture_default_str();
                break;
            case ParameterKind::Integer:
                option = app.add_option(flag, f.settings.*row.integer, help)->capture_default_str();
                break;
            case ParameterKind::Colour:
            case ParameterKind::Direction:
            case ParameterKind::Choice:
                // Parsed into the settings when given; parse_parameter names the setting.
                option = app.add_option_function<std::string>(
                                flag,
                                [&f, &row](const std::string& text) {
                                    parse_parameter(row, text, f.settings);
                                },
                                help)
                             ->default_str(format_parameter(row, defaults));
                if (row.kind == ParameterKind::Colour) option->type_name("R,G,B");
                if (row.kind == ParameterKind::Direction) option->type_name("X,Y,Z");
                break;
        }
        option->group(group);
    }
}

ShadingSettings resolve_shading(const ShadingFlags& f) {
    validate(f.settings);
    return f.settings;
}

glm::vec3 plane_glint_light(glm::vec3 view_dir) {
    const glm::vec3 v = glm::normalize(view_dir);
    return {-v.x, 1.15f * v.y, -v.z};
}

void apply_scene_light(ShadingFlags& flags, const CLI::App& app, const std::string& scene,
                       glm::vec3 view_dir) {
    if (scene != "plane" || app.count("--light-dir") > 0) return;
    flags.settings.light_direction = plane_glint_light(view_dir);
}

void set_shading_defaults(const ShadingSettings& settings, const CLI::App& app,
                          ShadingFlags& flags) {
    for (const ParameterInfo& row : shading_parameters()) {
        if (app.count(flag_for_setting(row.key)) > 0) continue;
        switch (row.kind) {
            case ParameterKind::Scalar:
                flags.settings.*row.scalar = settings.*row.scalar;
                break;
            case ParameterKind::Integer:
                flags.settings.*row.integer = settings.*row.integer;
                break;
            case ParameterKind::Colour:
            case ParameterKind::Direction:
                flags.settings.*row.vector = settings.*row.vector;
                break;
            case ParameterKind::Choice:
                row.set_choice(flags.settings, row.get_choice(settings));
                break;
        }
    }
}

void add_lean_source_options(CLI::App& app, scene::BumpMapSource& f) {
    const std::string group = "Bumps";
    std::string names;
    for (const std::string& n : builtin_bump_names()) names += (names.empty() ? "" : ", ") + n;
    app.add_option("--bumps", f.source,
                   "Built-in bump set (" + names +
                       "), a height/normal map image, or a .ktx2 LEAN map from `leanfade bake` "
                       "(an OBJ scene with MTL materials uses their bump maps unless --bumps "
                       "is given)")
        ->capture_default_str()
        ->each([&f](const std::string&) { f.replaces_obj_maps = true; })
        ->group(group);
    add_typed_option(
        app, "--from", f.from,
        [](const std::string& text) { return parse_bake_source(text, "--from"); },
        "Image inputs: " + name_list(bake_source_names()) +
            " (auto: 1-2 channels height, 3-4 normal, as bake)",
        to_string(f.from))
        ->group(group);
    app.add_flag("--directx", f.directx, "Normal maps use the DirectX convention (-Y)")
        ->group(group);
    app.add_flag("--strict-normals", f.strict_normals,
                 "Normal maps: refuse texels with z <= 0 instead of taking (0, 0, 0) padding as "
                 "flat and raising the others (counted and reported)")
        ->group(group);
    add_typed_option(
        app, "--bits", f.bits,
        [](const std::string& text) { return parse_storage_policy(text, "--bits"); },
        "Storage of on-the-fly bakes: " + name_list(bake_storage_names()) +
            " (auto: 16, or 16f/32f by the predicted error, as bake)",
        to_string(f.bits))
        ->group(group);
    add_typed_option(
        app, "--strength-unit", f.strength_unit,
        [](const std::string& text) {
            return text == "uv" ? StrengthUnit::Uv : StrengthUnit::Texel;
        },
        "Unit of --strength for height maps baked on the fly: texel (height per texel "
        "spacing) or uv (height per UV unit: the same slopes at any resolution)",
        f.strength_unit == StrengthUnit::Uv ? "uv" : "texel")
        ->check(CLI::IsMember({"texel", "uv"}))
        ->group(group);
    add_spike_option(app, f.spike, "Two-lobe LEAN's spike in on-the-fly bakes, as bake --spike")
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
    // A flag per surface map that a setting gives (the map kinds' table: its setting and help).
    for (const scene::MapKindInfo& row : scene::kMapKinds)
        if (!row.setting.empty())
            app.add_option(map_flag(row.kind), f.map_file(row.kind), std::string(row.flag_help))
                ->group(group);
}

std::string map_flag(scene::MapKind kind) {
    return "--" + std::string(scene::info(kind).setting);
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

CLI::Option* add_techniques_option(CLI::App& app, const std::string& flag,
                                   std::vector<Technique>& techniques, const std::string& help) {
    return add_typed_option(
        app, flag, techniques,
        [flag](const std::string& text) { return parse_techniques(text, flag); }, help,
        join_technique_names(techniques));
}

CLI::Option* add_size_option(CLI::App& app, const std::string& flag, FramebufferSize& size,
                             const std::string& help) {
    return add_typed_option(
        app, flag, size, [flag](const std::string& text) { return parse_size(text, flag); }, help,
        size_text(size));
}

CLI::Option* add_distance_sweep_option(CLI::App& app, std::vector<float>& distances,
                                       const std::string& help, const std::string& default_text) {
    return add_typed_option(
        app, "--distances", distances,
        [](const std::string& text) { return eval::parse_distance_sweep(text, "--distances"); },
        help, default_text);
}

void add_camera_options(CLI::App& app, float& fov, glm::vec3& view_dir, const char* view_from,
                        glm::vec3* target) {
    add_typed_option(
        app, "--fov", fov,
        [](const std::string& text) {
            float degrees = 0.0f;
            if (!parse_finite(text, degrees))
                throw Error("--fov", "expected a finite number, got '" + text + "'");
            check_field_of_view(degrees, "--fov");
            return degrees;
        },
        "Vertical field of view in degrees", number_text(fov));
    add_typed_option(
        app, "--view-dir", view_dir, parse_view_direction,
        std::string("Direction from ") + view_from + " toward the eye, world space (y up)",
        vector_text(view_dir));
    if (target != nullptr) {
        add_typed_option(
            app, "--target", *target,
            [](const std::string& text) {
                const glm::vec3 point = parse_vector(text, "--target");
                check_camera_target(point, "--target");
                return point;
            },
            "Point the camera looks at, world units (bounding radii; 0 = the centre)",
            vector_text(*target));
    }
}

void add_reference_samples_option(CLI::App& app, int& ref_samples) {
    app.add_option("--ref-samples", ref_samples,
                   "Reference: k x k samples per pixel at LOD 0 (docs/math.md §7)")
        ->capture_default_str();
}

glm::vec3 parse_view_direction(const std::string& text) {
    const glm::vec3 direction = parse_vector(text, "--view-dir");
    if (direction == glm::vec3(0.0f)) throw Error("--view-dir", "must not be the zero vector");
    return direction;
}

int checked_reference_samples(int k) {
    if (k < 1 || k > kMaxReferenceSamples)
        throw Error("--ref-samples", "must be in [1, " + std::to_string(kMaxReferenceSamples) +
                                         "], got " + std::to_string(k));
    return k;
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

}  // namespace leanfade::cli
