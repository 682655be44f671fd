#pragma once
// The shading code of every technique for other APIs (`leanfade shaders`, docs/integration.md):
// the renderer's vertex stage (scene.vert) once and the fragment stage (scene.frag) of every
// scene variant of shader_variants() (each technique of the table and the variant bits it has),
// as self-contained sources in one language:
//   glsl   GLSL 4.50 for OpenGL, as the renderer compiles it: the includes inlined, the variant's
//          #defines after #version (the #line directives of the resolution left out).
//   spirv  SPIR-V 1.0 for Vulkan 1.0, compiled from that GLSL by the glslang library (no
//          optimisation, names kept). Descriptor set 0; a texture's binding is its OpenGL texture
//          unit, a uniform block's is kSpirvUniformBlockBase + its OpenGL block binding; the
//          stage's inputs and outputs get consecutive locations in declaration order.
//   hlsl   HLSL shader model 5.0 cross-compiled from the SPIR-V by SPIRV-Cross: entry point
//          main, registers t<unit> and s<unit> for a texture, b<block binding> for a cbuffer.
//   msl    Metal Shading Language 2.2 cross-compiled from the SPIR-V by SPIRV-Cross: entry point
//          main0 (Metal reserves main), [[texture(unit)]], [[sampler(unit)]] and
//          [[buffer(block binding)]].
// Block, struct, member and sampler names are those of the GLSL (LfShadingBlock, u_shading,
// LfParams, u_lean, ...). GL-free: the tool's own library, not linked by the renderer.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "leanfade/gl/shader_library.hpp"

namespace leanfade::gl {

enum class ShaderLanguage { Glsl, Spirv, Hlsl, Msl };

const char* to_string(ShaderLanguage language);  // "glsl", "spirv", "hlsl", "msl"
// Every language's name, in enum order.
const std::vector<std::string>& shader_language_names();
// Throws leanfade::Error(setting, cause) for a name that is not a language's.
ShaderLanguage parse_shader_language(std::string_view name, const std::string& setting = "lang");
// The file extension of a language's files: ".glsl", ".spv", ".hlsl", ".metal".
const char* file_extension(ShaderLanguage language);

// A uniform block's SPIR-V binding is this + its OpenGL block binding: OpenGL numbers texture units
// and block bindings apart, a Vulkan descriptor set numbers them together. Texture units stay below
// it (16 is OpenGL's minimum GL_MAX_TEXTURE_IMAGE_UNITS); a shader with a texture at 16 or above is
// refused.
inline constexpr unsigned kSpirvUniformBlockBase = 16;

struct ExportedShader {
    std::string variant;               // "scene_lean_plain", or "scene" for the vertex stage
    std::string stage;                 // "vert" or "frag"
    std::string source;                // the file it comes from: "scene.frag"
    std::vector<std::string> defines;  // the variant's ("LF_TECHNIQUE 1", ...)
    std::string file_name;             // <variant>.<stage><extension>: "scene_lean.frag.spv"
    std::vector<std::uint8_t> bytes;   // the text, or the SPIR-V words (little-endian)
};

// The vertex stage, then every scene variant's fragment stage, in shader_variants() order.
// Throws leanfade::Error(<shader file>, <compiler message>) when glslang or SPIRV-Cross refuses a
// stage (a shader the renderer compiles is not refused).
std::vector<ExportedShader> export_shaders(const ShaderSources& sources, ShaderLanguage language);

}  // namespace leanfade::gl
