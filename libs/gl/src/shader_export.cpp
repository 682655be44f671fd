// The shading code of every technique for other APIs: GLSL as resolved, SPIR-V by the glslang
// library (its C interface), HLSL and MSL by SPIRV-Cross (its C interface, the shared library
// libspirv-cross-c-shared).
#include "leanfade/gl/shader_export.hpp"

#include <cstring>
#include <memory>
#include <mutex>
#include <regex>
#include <sstream>

#include <glslang/Include/glslang_c_interface.h>
#include <glslang/Public/resource_limits_c.h>
#include <spirv_cross/spirv_cross_c.h>

#include "leanfade/core/error.hpp"
#include "leanfade/core/input_text.hpp"
#include "leanfade/core/text.hpp"

namespace leanfade::gl {
namespace {

constexpr const char* kVertexFile = "scene.vert";
constexpr const char* kFragmentFile = "scene.frag";

// The GLSL file: the resolved text without its #line directives (they number the files of the
// resolution, which mean nothing in one file); where an included file starts and ends is marked
// by a comment instead.
std::string standalone_glsl(const ResolvedSource& resolved, const ShaderVariant* variant) {
    std::istringstream in(resolved.text);
    std::ostringstream out;
    std::string line;
    bool header_written = false;
    int current = 0;
    while (std::getline(in, line)) {
        if (line.rfind("#line ", 0) == 0) {
            std::istringstream fields(line.substr(6));
            int number = 0, file = 0;
            fields >> number >> file;
            if (file != current && file >= 0 && std::size_t(file) < resolved.files.size()) {
                out << "// ---- " << (number == 1 ? "begin " : "back in ")
                    << resolved.files[std::size_t(file)] << " ----\n";
                current = file;
            }
            continue;
        }
        out << line << "\n";
        if (!header_written) {  // after #version
            out << "// leanfade " << (variant != nullptr ? variant->name : std::string("scene"))
                << ": " << resolved.files.front() << " with its includes inlined, written by\n"
                << "// `leanfade shaders` from shaders/*.glsl (docs/integration.md)\n";
            header_written = true;
        }
    }
    return out.str();
}

// One glslang process for the program's lifetime (glslang_initialize_process is reference
// counted and not thread-safe).
void initialize_glslang() {
    static std::once_flag once;
    std::call_once(once, [] { glslang_initialize_process(); });
}

// A compiler's log as one line: its lines joined by "; ".
std::string one_line(const char* log) {
    std::string text = log != nullptr ? log : "";
    std::string out;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
        if (line.empty()) continue;
        out += (out.empty() ? "" : "; ") + line;
    }
    return out.empty() ? "no message" : out;
}

struct ShaderDeleter {
    void operator()(glslang_shader_t* s) const { glslang_shader_delete(s); }
};
struct ProgramDeleter {
    void operator()(glslang_program_t* p) const { glslang_program_delete(p); }
};

// GLSL 4.50 -> SPIR-V 1.0 for Vulkan 1.0 (see the header for bindings and locations). Errors are
// given as the renderer gives a driver's (compile_error: file and line of the first error).
std::vector<std::uint32_t> compile_spirv(const ShaderSources& sources, const std::string& file,
                                         const ResolvedSource& resolved, bool fragment) {
    initialize_glslang();
    glslang_input_t input{};
    input.language = GLSLANG_SOURCE_GLSL;
    input.stage = fragment ? GLSLANG_STAGE_FRAGMENT : GLSLANG_STAGE_VERTEX;
    input.client = GLSLANG_CLIENT_VULKAN;
    input.client_version = GLSLANG_TARGET_VULKAN_1_0;
    input.target_language = GLSLANG_TARGET_SPV;
    input.target_language_version = GLSLANG_TARGET_SPV_1_0;
    input.code = resolved.text.c_str();
    input.default_version = 450;
    input.default_profile = GLSLANG_CORE_PROFILE;
    input.messages = GLSLANG_MSG_DEFAULT_BIT;
    input.resource = glslang_default_resource();
    const GLenum stage = fragment ? GL_FRAGMENT_SHADER : GL_VERTEX_SHADER;

    std::unique_ptr<glslang_shader_t, ShaderDeleter> shader(glslang_shader_create(&input));
    if (!shader) throw Error(file, "glslang could not create a shader");
    glslang_shader_set_options(shader.get(), GLSLANG_SHADER_AUTO_MAP_LOCATIONS);
    glslang_shader_shift_binding(shader.get(), GLSLANG_RESOURCE_TYPE_UBO, kSpirvUniformBlockBase);
    if (!glslang_shader_preprocess(shader.get(), &input) ||
        !glslang_shader_parse(shader.get(), &input))
        throw compile_error(stage, file, resolved, sources,
                            glslang_shader_get_info_log(shader.get()));

    std::unique_ptr<glslang_program_t, ProgramDeleter> program(glslang_program_create());
    glslang_program_add_shader(program.get(), shader.get());
    const int rules = GLSLANG_MSG_SPV_RULES_BIT | GLSLANG_MSG_VULKAN_RULES_BIT;
    if (!glslang_program_link(program.get(), rules) || !glslang_program_map_io(program.get()))
        throw Error(file, "glslang: " + one_line(glslang_program_get_info_log(program.get())));
    glslang_spv_options_t options{};
    options.disable_optimizer = true;  // names and structure as written
    options.validate = true;
    glslang_program_SPIRV_generate_with_options(program.get(), input.stage, &options);
    const char* messages = glslang_program_SPIRV_get_messages(program.get());
    if (messages != nullptr && std::strstr(messages, "error") != nullptr)
        throw Error(file, "glslang: " + one_line(messages));
    std::vector<std::uint32_t> words(glslang_program_SPIRV_get_size(program.get()));
    if (words.empty()) throw Error(file, "glslang produced no SPIR-V");
    glslang_program_SPIRV_get(program.get(), words.data());
    return words;
}

struct ContextDeleter {
    void operator()(spvc_context_s* c) const { spvc_context_destroy(c); }
};

// The resources of a stage, checked and numbered in the target language from their OpenGL
// numbers: in SPIR-V a texture's binding is its unit and a uniform block's is
// kSpirvUniformBlockBase + its block binding; HLSL gets t<unit>, s<unit> and b<block binding>, MSL
// [[texture(unit)]], [[sampler(unit)]] and [[buffer(block binding)]] (without this SPIRV-Cross
// would number Metal's arguments in order of appearance, which changes from variant to variant).
// A texture unit at kSpirvUniformBlockBase or above would share a SPIR-V binding with a block and
// is refused.
template <typename Fail>
void bind_resources(spvc_compiler compiler, ShaderLanguage language, const std::string& file,
                    const Fail& fail) {
    spvc_resources resources = nullptr;
    if (spvc_compiler_create_shader_resources(compiler, &resources) != SPVC_SUCCESS)
        throw fail("cannot list the resources");
    const SpvExecutionModel model = spvc_compiler_get_execution_model(compiler);
    for (const spvc_resource_type type :
         {SPVC_RESOURCE_TYPE_UNIFORM_BUFFER, SPVC_RESOURCE_TYPE_SAMPLED_IMAGE}) {
        const spvc_reflected_resource* list = nullptr;
        std::size_t count = 0;
        if (spvc_resources_get_resource_list_for_type(resources, type, &list, &count) !=
            SPVC_SUCCESS)
            throw fail("cannot list the resources");
        for (std::size_t i = 0; i < count; ++i) {
            const unsigned set =
                spvc_compiler_get_decoration(compiler, list[i].id, SpvDecorationDescriptorSet);
            const unsigned binding =
                spvc_compiler_get_decoration(compiler, list[i].id, SpvDecorationBinding);
            const bool block = type == SPVC_RESOURCE_TYPE_UNIFORM_BUFFER;
            if (!block && binding >= kSpirvUniformBlockBase)
                throw Error(file, std::string("the texture ") + list[i].name + " is at unit " +
                                      std::to_string(binding) +
                                      ", which SPIR-V gives to uniform "
                                      "blocks (units below " +
                                      std::to_string(kSpirvUniformBlockBase) +
                                      " only, shaders/bindings.glsl)");
            const unsigned gl_number = block ? binding - kSpirvUniformBlockBase : binding;
            if (language == ShaderLanguage::Hlsl) {
                spvc_hlsl_resource_binding hlsl;
                spvc_hlsl_resource_binding_init(&hlsl);
                hlsl.stage = model;
                hlsl.desc_set = set;
                hlsl.binding = binding;
                hlsl.cbv.register_binding = gl_number;
                hlsl.srv.register_binding = gl_number;
                hlsl.sampler.register_binding = gl_number;
                if (spvc_compiler_hlsl_add_resource_binding(compiler, &hlsl) != SPVC_SUCCESS)
                    throw fail("cannot bind a resource");
            } else if (language == ShaderLanguage::Msl) {
                spvc_msl_resource_binding msl;
                spvc_msl_resource_binding_init(&msl);
                msl.stage = model;
                msl.desc_set = set;
                msl.binding = binding;
                msl.msl_buffer = gl_number;
                msl.msl_texture = gl_number;
                msl.msl_sampler = gl_number;
                if (spvc_compiler_msl_add_resource_binding(compiler, &msl) != SPVC_SUCCESS)
                    throw fail("cannot bind a resource");
            }
        }
    }
}

// SPIRV-Cross 2021 (Debian 12) translates textureQueryLod on a 2D array texture to
// `t.CalculateLevelOfDetail(s, uv.xyz)` with a 2-component uv, which no HLSL compiler accepts
// (fixed upstream: KhronosGroup/SPIRV-Cross issue 2553). A Texture2DArray's LOD takes the 2D
// location, so the swizzle becomes .xy. (Its .y, the unclamped LOD of GLSL, is given the clamped
// one as SPIRV-Cross always does in HLSL.)
std::string fix_hlsl_lod_queries(std::string hlsl) {
    static const std::regex declaration(R"(Texture2DArray<[^>]*>\s+(\w+))");
    std::vector<std::string> textures;
    for (std::sregex_iterator it(hlsl.begin(), hlsl.end(), declaration), end; it != end; ++it)
        textures.push_back((*it)[1].str());
    for (const std::string& texture : textures) {
        // <texture>[index].CalculateLevelOfDetail(<sampler>, <uv>.xyz)
        const std::regex query("\\b(" + texture + R"((\[[^\]]*\])?\.CalculateLevelOfDetail)" +
                               R"(\([^,()]+,\s*[\w.]+)\.xyz\))");
        hlsl = std::regex_replace(hlsl, query, "$1.xy)");
    }
    return hlsl;
}

// SPIR-V -> HLSL 5.0 or MSL by SPIRV-Cross; for SPIR-V itself, only the check of its bindings
// (returns "").
std::string cross_compile(const std::string& file, const std::vector<std::uint32_t>& words,
                          ShaderLanguage language) {
    spvc_context raw = nullptr;
    if (spvc_context_create(&raw) != SPVC_SUCCESS) throw Error(file, "SPIRV-Cross: no context");
    std::unique_ptr<spvc_context_s, ContextDeleter> context(raw);
    auto fail = [&](const char* what) {
        return Error(file, std::string("SPIRV-Cross ") + what + ": " +
                               one_line(spvc_context_get_last_error_string(context.get())));
    };
    spvc_parsed_ir ir = nullptr;
    if (spvc_context_parse_spirv(context.get(), words.data(), words.size(), &ir) != SPVC_SUCCESS)
        throw fail("cannot parse the SPIR-V");
    const spvc_backend backend = language == ShaderLanguage::Hlsl  ? SPVC_BACKEND_HLSL
                                 : language == ShaderLanguage::Msl ? SPVC_BACKEND_MSL
                                                                   : SPVC_BACKEND_NONE;
    spvc_compiler compiler = nullptr;
    if (spvc_context_create_compiler(context.get(), backend, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP,
                                     &compiler) != SPVC_SUCCESS)
        throw fail("has no compiler");
    bind_resources(compiler, language, file, fail);
    if (backend == SPVC_BACKEND_NONE) return {};
    spvc_compiler_options options = nullptr;
    if (spvc_compiler_create_compiler_options(compiler, &options) != SPVC_SUCCESS)
        throw fail("has no options");
    if (language == ShaderLanguage::Hlsl)
        spvc_compiler_options_set_uint(options, SPVC_COMPILER_OPTION_HLSL_SHADER_MODEL, 50);
    else  // arrays of textures (bump layers) need MSL 2.0, textureQueryLod 2.2
        spvc_compiler_options_set_uint(options, SPVC_COMPILER_OPTION_MSL_VERSION,
                                       SPVC_MAKE_MSL_VERSION(2, 2, 0));
    spvc_compiler_install_compiler_options(compiler, options);
    const char* result = nullptr;
    if (spvc_compiler_compile(compiler, &result) != SPVC_SUCCESS || result == nullptr)
        throw fail("cannot translate it");
    return language == ShaderLanguage::Hlsl ? fix_hlsl_lod_queries(result) : std::string(result);
}

std::vector<std::uint8_t> text_bytes(const std::string& text) {
    return std::vector<std::uint8_t>(text.begin(), text.end());
}

ExportedShader export_stage(const ShaderSources& sources, const ShaderVariant* variant,
                            ShaderLanguage language) {
    const bool fragment = variant != nullptr;
    ExportedShader out;
    out.variant = fragment ? variant->name : "scene";
    out.stage = fragment ? "frag" : "vert";
    out.source = fragment ? kFragmentFile : kVertexFile;
    if (fragment) out.defines = variant->defines;
    out.file_name = out.variant + "." + out.stage + file_extension(language);
    const ResolvedSource resolved = sources.resolve(out.source, out.defines);
    if (language == ShaderLanguage::Glsl) {
        out.bytes = text_bytes(standalone_glsl(resolved, variant));
        return out;
    }
    const std::vector<std::uint32_t> words = compile_spirv(sources, out.source, resolved, fragment);
    if (language == ShaderLanguage::Spirv) {
        cross_compile(out.source, words, language);  // checks the bindings
        out.bytes.reserve(words.size() * 4);
        for (const std::uint32_t w : words)
            for (int shift = 0; shift < 32; shift += 8)
                out.bytes.push_back(std::uint8_t(w >> shift));
        return out;
    }
    out.bytes = text_bytes(cross_compile(out.source, words, language));
    return out;
}

}  // namespace

const char* to_string(ShaderLanguage language) {
    return shader_language_names()[std::size_t(language)].c_str();
}

const std::vector<std::string>& shader_language_names() {
    static const std::vector<std::string> names{"glsl", "spirv", "hlsl", "msl"};
    return names;
}

ShaderLanguage parse_shader_language(std::string_view name, const std::string& setting) {
    const std::vector<std::string>& names = shader_language_names();
    for (std::size_t i = 0; i < names.size(); ++i)
        if (name == names[i]) return ShaderLanguage(i);
    throw Error(setting, "unknown shader language '" + escape_text(std::string(name)) +
                             "' (expected " + name_list(names) + ")");
}

const char* file_extension(ShaderLanguage language) {
    switch (language) {
        case ShaderLanguage::Glsl:
            return ".glsl";
        case ShaderLanguage::Spirv:
            return ".spv";
        case ShaderLanguage::Hlsl:
            return ".hlsl";
        case ShaderLanguage::Msl:
            return ".metal";
    }
    return "";
}

std::vector<ExportedShader> export_shaders(const ShaderSources& sources, ShaderLanguage language) {
    std::vector<ExportedShader> shaders;
    shaders.push_back(export_stage(sources, nullptr, language));
    for (const ShaderVariant& variant : shader_variants())
        if (variant.vertex == kVertexFile && variant.fragment == kFragmentFile)
            shaders.push_back(export_stage(sources, &variant, language));
    return shaders;
}

}  // namespace leanfade::gl
