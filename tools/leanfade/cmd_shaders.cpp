// leanfade shaders: the shading code of every technique for other APIs (GLSL, SPIR-V, HLSL, MSL),
// one file per stage and variant, and an index (shaders.json). docs/integration.md.
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/gl/detail/figure.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/gl/detail/shader_export.hpp"
#include "leanfade/gl/detail/shading_block.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/scene/detail/map_kinds.hpp"
#include "leanfade/scene/detail/mesh.hpp"
#include "leanfade/scene/detail/vertex_layout.hpp"
#include "leanfade/version.hpp"

namespace leanfade::cli {
namespace {

namespace fs = std::filesystem;

struct ShadersArgs {
    std::string lang;
    std::string out_dir;
    std::string shaders;  // a folder of shader sources instead of the embedded ones
};

constexpr const char* kIndexFile = "shaders.json";

// A SPIR-V module's reflection (docs/integration.md, "shaders.json"): what a Vulkan pipeline
// layout and vertex input state are made from.
nlohmann::json reflection_json(const gl::ShaderReflection& r) {
    nlohmann::json resources = nlohmann::json::array();
    for (const gl::ShaderResource& res : r.resources) {
        nlohmann::json j{{"name", res.name},       {"descriptor_type", res.descriptor_type},
                         {"type", res.type},       {"set", res.set},
                         {"binding", res.binding}, {"array_size", res.array_size},
                         {"stage", r.stage}};
        if (res.descriptor_type == "uniform_buffer") {
            j["block_size"] = res.block_size;
            nlohmann::json members = nlohmann::json::array();
            for (const gl::ShaderBlockMember& m : res.members) {
                nlohmann::json member{
                    {"name", m.name}, {"type", m.type}, {"offset", m.offset}, {"size", m.size}};
                if (m.array_size > 0) {
                    member["array_size"] = m.array_size;
                    member["array_stride"] = m.array_stride;
                }
                if (m.matrix_stride > 0) member["matrix_stride"] = m.matrix_stride;
                members.push_back(member);
            }
            j["members"] = members;
        }
        resources.push_back(j);
    }
    auto variables = [](const std::vector<gl::ShaderInterfaceVariable>& list, bool formats) {
        nlohmann::json out = nlohmann::json::array();
        for (const gl::ShaderInterfaceVariable& v : list) {
            nlohmann::json j{{"name", v.name}, {"location", v.location}, {"type", v.type}};
            if (formats && !v.format.empty()) j["format"] = v.format;
            out.push_back(j);
        }
        return out;
    };
    const bool vertex = r.stage == "vertex";
    return {{"stage", r.stage},
            {"entry_point", r.entry_point},
            {"resources", resources},
            {"inputs", variables(r.inputs, vertex)},
            {"outputs", variables(r.outputs, false)}};
}

nlohmann::json values_json(const std::vector<gl::BlockValue>& values) {
    nlohmann::json out = nlohmann::json::array();
    for (const gl::BlockValue& v : values) {
        nlohmann::json j{{"name", v.name}, {"type", v.type}};
        if (v.values.size() == 1)
            j["value"] = v.values.front();
        else
            j["value"] = v.values;
        out.push_back(j);
    }
    return out;
}

nlohmann::json vec3_json(glm::vec3 v) {
    return nlohmann::json::array({v.x, v.y, v.z});
}

// What `leanfade render` draws with when given no flags (docs/integration.md, "shaders.json"),
// so that another program draws the same picture: the variant per technique, the shading
// block's members (its map's scale sc and the bits of the maps bound are the program's), the
// object block's light and tiling (its matrices and eye follow the camera below) and the camera.
nlohmann::json defaults_json() {
    const ShadingSettings settings;
    nlohmann::json variants;
    for (const Technique technique : all_techniques()) {
        gl::RenderRequest request;
        request.technique = technique;
        variants[std::string(info(technique).name)] = gl::variant_name(gl::variant_for(request));
    }
    const shading::LfShadingUniforms shading =
        gl::shading_uniforms(settings, false, 1.0f, 1.0f, gl::OutputMode::Color);
    gl::LfObjectUniforms object{};
    object.tiling = settings.tiling;
    object.light_world = glm::normalize(settings.light_direction);
    std::vector<gl::BlockValue> object_values;
    for (gl::BlockValue& v : gl::std140_block_values(gl::kObjectBlockFields, &object, ""))
        if (v.name == "u_tiling" || v.name == "u_light_world") object_values.push_back(std::move(v));
    const gl::FigureRequest figure;
    return {
        {"variants", variants},
        {"blocks",
         {{"LfShadingBlock",
           values_json(gl::std140_block_values(gl::kShadingBlockFields, &shading, "u_shading."))},
          {"LfObjectBlock", values_json(object_values)}}},
        {"camera",
         {{"fov_y_degrees", gl::kDefaultFovYDegrees},
          {"view_direction", vec3_json(kDefaultViewDirection)},
          {"target", vec3_json(glm::vec3(0.0f))},
          {"up", "(0, 1, 0); (0, 0, -1) when the view direction is within 0.0001 of the y axis"},
          {"near_plane", "max(0.01, 0.9 (d - 1)) for the eye d bounding radii from the centre"},
          {"far_plane", "1.1 (d + 1)"},
          {"model", "the object scaled by 1 / its bounding radius (half its box's diagonal) about "
                    "its box's centre"},
          {"background", vec3_json(figure.background)}}},
        {"sampler",
         "trilinear (LINEAR_MIPMAP_LINEAR), repeating, every MIP level; rows of the KTX2 levels "
         "uploaded bottom first (+v up)"}};
}

// The surface maps a variant may sample, from the map-kind table (leanfade/scene/detail/map_kinds.hpp):
// where each is bound, its bit in u_shading.maps and its slot of u_shading.uv_transforms, and what
// to bind when a material has none.
nlohmann::json maps_json() {
    nlohmann::json list = nlohmann::json::array();
    for (const scene::MapKindInfo& m : scene::kMapKinds) {
        list.push_back(
            {{"name", std::string(m.name)},
             {"binding", m.binding},
             {"maps_bit", m.mask_bit},
             {"uv_transform", m.uv_transform},
             {"channels", m.channels},
             {"format", m.format == scene::MapFormat::R32f ? "R32F" : "RGBA16F"},
             {"cook_torrance_only", m.cook_torrance_only},
             {"when_absent",
              m.fallback == scene::MapFallback::White
                  ? "bind a 1x1 white texture (a factor of 1); the bit may stay 0"
                  : "keep the bit 0 and bind any texture of the sampler's type where the "
                    "variant's reflection lists the binding: it is not sampled"},
             {"gltf_source", std::string(m.gltf_source)},
             {"meaning", std::string(m.meaning)}});
    }
    return list;
}

// The vertex input every variant's vertex stage reads (scene::Vertex), one interleaved binding.
nlohmann::json vertex_layout_json() {
    nlohmann::json attributes = nlohmann::json::array();
    for (const scene::VertexAttribute& a : scene::kVertexAttributes)
        attributes.push_back({{"location", a.location},
                              {"name", a.name},
                              {"components", a.components},
                              {"type", "float32"},
                              {"offset", a.offset}});
    return {{"stride", sizeof(scene::Vertex)}, {"attributes", attributes}};
}

nlohmann::json index_json(gl::ShaderLanguage language,
                          const std::vector<gl::ExportedShader>& shaders) {
    nlohmann::json j;
    j["generator"] = std::string(LEANFADE_GENERATOR);
    j["language"] = gl::to_string(language);
    // A block's binding (SPIR-V) or register (b, [[buffer]]) = this + its OpenGL block binding;
    // textures keep their OpenGL units everywhere.
    const bool wgsl = language == gl::ShaderLanguage::Wgsl;
    j["uniform_block_binding_offset"] =
        language == gl::ShaderLanguage::Spirv || wgsl ? gl::kSpirvUniformBlockBase : 0u;
    if (wgsl) {
        // WGSL has no combined samplers: each texture's sampler has a binding of its own.
        j["sampler_binding_offset"] = gl::kWgslSamplerBindingOffset;
        j["translator"] = "naga (npm naga-wasm) from the optimised SPIR-V, samplers split";
        j["bindings"] =
            "@group(0): a texture at its OpenGL unit, its sampler at sampler_binding_offset + "
            "that unit, a uniform block at uniform_block_binding_offset + its block binding";
    }
    nlohmann::json list = nlohmann::json::array();
    const bool spirv = language == gl::ShaderLanguage::Spirv;
    if (spirv) j["optimizer"] = "SPIRV-Tools performance passes (spirv-opt -O)";
    const bool es = language == gl::ShaderLanguage::GlslEs;
    if (es)
        j["bindings"] =
            "GLSL ES 3.00 has no layout bindings: set each sampler's unit (uniform1i) and each "
            "block's binding (uniformBlockBinding) by name, as the reflection's binding gives";
    for (const gl::ExportedShader& s : shaders) {
        nlohmann::json entry{{"variant", s.variant}, {"stage", s.stage},
                             {"source", s.source},   {"defines", s.defines}};
        if (!s.omitted.empty()) {
            entry["omitted"] = s.omitted;  // no file
        } else {
            entry["file"] = s.file_name;
            entry["size"] = s.bytes.size();
        }
        if (spirv) entry["unoptimised_size"] = s.unoptimised_size;
        if (spirv || es || wgsl) entry["reflection"] = reflection_json(s.reflection);
        list.push_back(entry);
    }
    j["shaders"] = list;
    j["defaults"] = defaults_json();
    j["maps"] = maps_json();
    j["vertex_layout"] = vertex_layout_json();
    return j;
}

// Every shader is compiled before anything is written: a refused one leaves no output.
int run_shaders(const ShadersArgs& args) {
    const gl::ShaderLanguage language = gl::parse_shader_language(args.lang, "--lang");
    const gl::ShaderSources sources = args.shaders.empty()
                                          ? gl::ShaderSources::embedded()
                                          : gl::ShaderSources::directory(args.shaders);

    io::OutputPlan plan;
    plan.add_output_folder(args.out_dir, true);
    const std::string index_path = (fs::path(args.out_dir) / kIndexFile).string();
    plan.add_output(index_path, "the index");
    // The output names do not depend on the compilation: checked first.
    const std::vector<gl::ExportedShader> shaders = gl::export_shaders(
        sources, language,
        language == gl::ShaderLanguage::Wgsl ? gl::find_wgsl_translator() : std::string());
    std::size_t written = 0;
    for (const gl::ExportedShader& s : shaders) {
        if (!s.omitted.empty()) continue;
        plan.add_output((fs::path(args.out_dir) / s.file_name).string(), s.variant);
        ++written;
    }
    plan.check();

    // Written into a staging folder beside the output folder, published together.
    io::OutputTransaction outputs;
    const fs::path staged = outputs.stage_folder(args.out_dir);
    auto write = [&](const std::string& name, const void* data, std::size_t size) {
        io::AtomicFile file((staged / name).string());
        file.write(data, size);
        file.commit();
    };
    for (const gl::ExportedShader& s : shaders)
        if (s.omitted.empty()) write(s.file_name, s.bytes.data(), s.bytes.size());
    const std::string index = index_json(language, shaders).dump(2) + "\n";
    write(kIndexFile, index.data(), index.size());
    outputs.publish();
    std::printf("%zu %s shaders (the vertex stage and %zu fragment variants) and %s in %s\n",
                written, gl::to_string(language), written - 1, kIndexFile, args.out_dir.c_str());
    if (written < shaders.size())
        std::printf("%zu variants have no %s form (shaders.json says why)\n",
                    shaders.size() - written, gl::to_string(language));
    if (language == gl::ShaderLanguage::Spirv) {
        std::size_t before = 0, after = 0;
        for (const gl::ExportedShader& s : shaders) {
            before += s.unoptimised_size;
            after += s.bytes.size();
        }
        std::printf("SPIR-V optimised: %zu bytes in all, %zu before optimisation\n", after, before);
    }
    return 0;
}

const CommandRegistration registration{
    "shaders", "Write the shading code of every technique for other APIs (GLSL, SPIR-V, HLSL, MSL, GLSL ES, WGSL)",
    [](CLI::App& app) -> Runner {
        auto args = std::make_shared<ShadersArgs>();
        app.add_option("--lang", args->lang,
                       "glsl (OpenGL 4.5 source), spirv (Vulkan 1.0, by glslang, optimised, "
                       "reflected in shaders.json), hlsl (shader model 5.0), msl (Metal) or "
                       "glsl-es (GLSL ES 3.00 for WebGL2, reflected; the three by SPIRV-Cross) or wgsl "
                       "(WebGPU, by naga under Node.js, reflected)")
            ->required();
        app.add_option("-o,--out-dir", args->out_dir,
                       "folder for one file per stage and variant and shaders.json (created when "
                       "missing)")
            ->required();
        app.add_option("--shaders", args->shaders,
                       "a folder of shader sources to use instead of the built-in ones");
        return [args] { return run_shaders(*args); };
    }};

}  // namespace
}  // namespace leanfade::cli
