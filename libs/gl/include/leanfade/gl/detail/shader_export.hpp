#pragma once
// The shading code of every technique for other APIs (`leanfade shaders`, docs/integration.md):
// the renderer's vertex stage (scene.vert) once and the fragment stage (scene.frag) of every
// scene variant of shader_variants() (each technique of the table and the variant bits it has),
// as self-contained sources in one language:
//   glsl   GLSL 4.50 for OpenGL, as the renderer compiles it: the includes inlined, the variant's
//          #defines after #version (the #line directives of the resolution left out).
//   spirv  SPIR-V 1.0 for Vulkan 1.0, compiled from that GLSL by the glslang library, then
//          optimised by SPIRV-Tools (its performance passes, as `spirv-opt -O`) and validated
//          for Vulkan 1.0: a module declares only the resources its variant reads. Names of
//          what remains are kept. Descriptor set 0; a texture's binding is its OpenGL texture
//          unit, a uniform block's is kSpirvUniformBlockBase + its OpenGL block binding; the
//          stage's inputs and outputs get consecutive locations in declaration order. Each
//          module comes with its reflection (ShaderReflection).
//   hlsl   HLSL shader model 5.0 cross-compiled by SPIRV-Cross from the unoptimised SPIR-V (so
//          that the functions keep their names): entry point main, registers t<unit> and
//          s<unit> for a texture, b<block binding> for a cbuffer.
//   msl    Metal Shading Language 2.2 cross-compiled by SPIRV-Cross from the unoptimised SPIR-V:
//          entry point main0 (Metal reserves main), [[texture(unit)]], [[sampler(unit)]] and
//          [[buffer(block binding)]].
//   glsl-es GLSL ES 3.00 for WebGL2 and OpenGL ES 3.0, cross-compiled by SPIRV-Cross from the
//          unoptimised SPIR-V and checked by glslang as GLSL ES 3.00. ES 3.00 has no layout
//          bindings: the application sets each sampler's unit (gl.uniform1i) and each block's
//          binding (gl.uniformBlockBinding) by name, from the reflection (OpenGL units and block
//          bindings). The vertex stage's outputs and the fragment stage's inputs, which ES matches
//          by name, are named lf_vertex_<member> in both. A variant ES 3.00 cannot express (the
//          roughness MIPs query the LOD and the level count) is listed with the reason
//          (ExportedShader::omitted) and no file.
//   wgsl   WGSL for WebGPU, translated by naga (the npm package naga-wasm, run by Node.js) from
//          the optimised SPIR-V with each combined sampler split into a texture at its OpenGL unit
//          and a sampler at kWgslSamplerBindingOffset + that unit (WGSL has no combined
//          samplers), uniform blocks at kSpirvUniformBlockBase + their block binding, all in
//          @group(0). The files start with `diagnostic(off, derivative_uniformity);`: the
//          shaders sample with implicit derivatives in branches that are uniform in practice
//          (per-material settings), which WGSL's static analysis cannot prove. Reflected like
//          SPIR-V. Variants with arrays of textures (bump layers; WebGPU has none) and
//          those naga refuses (a LOD query: the roughness MIPs) are omitted with the reason.
// Block, struct, member and sampler names are those of the GLSL (LfShadingBlock, u_shading,
// LfParams, u_lean, ...). GL-free: the tool's own library, not linked by the renderer.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "leanfade/gl/shader_library.hpp"

namespace leanfade::gl {

enum class ShaderLanguage { Glsl, Spirv, Hlsl, Msl, GlslEs, Wgsl };

const char* to_string(ShaderLanguage language);  // "glsl", "spirv", "hlsl", "msl", "glsl-es", "wgsl"
// Every language's name, in enum order.
const std::vector<std::string>& shader_language_names();
// Throws leanfade::Error(setting, cause) for a name that is not a language's.
ShaderLanguage parse_shader_language(std::string_view name, const std::string& setting = "lang");
// The file extension of a language's files: ".glsl", ".spv", ".hlsl", ".metal", ".essl", ".wgsl".
const char* file_extension(ShaderLanguage language);

// A uniform block's SPIR-V binding is this + its OpenGL block binding: OpenGL numbers texture units
// and block bindings apart, a Vulkan descriptor set numbers them together. Texture units stay below
// it (16 is OpenGL's minimum GL_MAX_TEXTURE_IMAGE_UNITS); a shader with a texture at 16 or above is
// refused.
inline constexpr unsigned kSpirvUniformBlockBase = 16;
// WGSL: a texture's sampler is at this + its unit (after the blocks' bindings).
inline constexpr unsigned kWgslSamplerBindingOffset = 32;

// A member of a uniform block, nested structs flattened ("u_shading.params.light_color").
struct ShaderBlockMember {
    std::string name;
    std::string type;                 // GLSL type: "float", "int", "vec3", "vec4", "mat3", "mat4"
    std::uint32_t offset = 0;         // bytes from the start of the block
    std::uint32_t size = 0;           // bytes the member declares (an array: all its elements)
    std::uint32_t array_size = 0;     // elements of an array, 0 for a member that is not one
    std::uint32_t array_stride = 0;   // bytes from element to element of an array
    std::uint32_t matrix_stride = 0;  // bytes from column to column of a matrix
};

// A resource a module reads: one descriptor of a Vulkan pipeline layout.
struct ShaderResource {
    std::string name;             // the sampler ("u_lean") or the block's type ("LfShadingBlock")
    // "combined_image_sampler" or "uniform_buffer"; WGSL: "sampled_texture" and "sampler"
    // instead of a combined one
    std::string descriptor_type;
    // "sampler2D", "sampler2DArray", or the block's name; WGSL: "texture_2d<f32>",
    // "texture_2d_array<f32>" and "sampler"
    std::string type;
    std::uint32_t set = 0;
    std::uint32_t binding = 0;
    std::uint32_t array_size = 1;            // descriptors (u_layer_maps[4]: 4)
    std::uint32_t block_size = 0;            // uniform_buffer: bytes the block declares (std140)
    std::vector<ShaderBlockMember> members;  // uniform_buffer: every member, by offset
};

// A stage input or output (a block's members one by one, "VertexData.uv").
struct ShaderInterfaceVariable {
    std::string name;
    std::uint32_t location = 0;
    std::string type;    // GLSL type: "vec2", "vec3", "vec4", "float"
    std::string format;  // the Vulkan format of a vertex attribute of that type: "R32G32B32_SFLOAT"
};

// What a pipeline needs to know about a SPIR-V module (SPIRV-Cross's reflection of the module as
// exported): its entry point, the resources it reads (and only those) by set and binding, its
// inputs and outputs by location (built-ins left out).
struct ShaderReflection {
    std::string stage;        // "vertex" or "fragment"
    std::string entry_point;  // "main"
    std::vector<ShaderResource> resources;
    std::vector<ShaderInterfaceVariable> inputs;
    std::vector<ShaderInterfaceVariable> outputs;
};

struct ExportedShader {
    std::string variant;               // "scene_lean_plain", or "scene" for the vertex stage
    std::string stage;                 // "vert" or "frag"
    std::string source;                // the file it comes from: "scene.frag"
    std::vector<std::string> defines;  // the variant's ("LF_TECHNIQUE 1", ...)
    std::string file_name;             // <variant>.<stage><extension>: "scene_lean.frag.spv"
    std::vector<std::uint8_t> bytes;   // the text, or the SPIR-V words (little-endian)
    // SPIR-V only: the bytes glslang wrote before optimisation. SPIR-V and GLSL ES: the module's
    // reflection (GLSL ES: of the unoptimised module, with OpenGL's texture units and block
    // bindings).
    std::size_t unoptimised_size = 0;
    ShaderReflection reflection;
    // GLSL ES and WGSL only: why the variant has no form in the language ("" when it has one;
    // otherwise `bytes` is empty and no file is written).
    std::string omitted;
};

// The reflection of a SPIR-V module (words in host order). Throws leanfade::Error(file, cause)
// when SPIRV-Cross cannot parse it.
ShaderReflection reflect_spirv(const std::vector<std::uint32_t>& words, const std::string& file);

// The vertex stage, then every scene variant's fragment stage, in shader_variants() order.
// Throws leanfade::Error(<shader file>, <compiler message>) when glslang or SPIRV-Cross refuses a
// stage (a shader the renderer compiles is not refused). WGSL needs `wgsl_translator`, the
// translator script (find_wgsl_translator); Error("lang", ...) without it or without Node.js,
// Error(<variant file>, <naga's message>) when naga refuses a module.
std::vector<ExportedShader> export_shaders(const ShaderSources& sources, ShaderLanguage language,
                                           const std::string& wgsl_translator = {});

// The WGSL translator installed with the program that runs (io::find_node_script of
// spirv_to_wgsl.mjs: tools/node in a build tree, share/leanfade/node when installed). "" when
// neither place has it.
std::string find_wgsl_translator();

// One module's WGSL, or why naga refused it (a construct WGSL lacks: a LOD query).
struct WgslTranslation {
    std::string text;
    std::string refused;
};

// SPIR-V modules (split samplers) -> WGSL, all in one run of `node <translator> IN OUT` (no
// shell) over a private temporary folder. Returns one translation per module, in order. Throws
// Error("lang", ...) without Node.js, Error(<translator>, ...) when the translator cannot run.
std::vector<WgslTranslation> translate_spirv_to_wgsl(
    const std::vector<std::vector<std::uint32_t>>& modules, const std::vector<std::string>& names,
    const std::string& translator);

}  // namespace leanfade::gl
