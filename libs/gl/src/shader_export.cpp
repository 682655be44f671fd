// The shading code of every technique for other APIs: GLSL as resolved, SPIR-V by the glslang
// library (its C interface) optimised and validated by SPIRV-Tools (its C++ API, linked with
// glslang's SPIR-V back end), HLSL and MSL by SPIRV-Cross (its C interface, the shared library
// libspirv-cross-c-shared), which also reflects the SPIR-V modules.
#include "leanfade/gl/detail/shader_export.hpp"

#include <algorithm>
#include <cstring>
#include <memory>
#include <mutex>
#include <regex>
#include <sstream>
#include <tuple>

#include <glslang/Include/glslang_c_interface.h>
#include <glslang/Public/resource_limits_c.h>
#include <spirv_cross/spirv_cross_c.h>
#include <spirv-tools/libspirv.hpp>
#include <spirv-tools/optimizer.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/text.hpp"
#include "spirv_samplers.hpp"

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

// glslang's input for one stage of GLSL source `text` (which must outlive it) of `version` and
// `profile`, with glslang initialised; the caller sets the client and target.
glslang_input_t glslang_input(const std::string& text, bool fragment, int version,
                              glslang_profile_t profile) {
    initialize_glslang();
    glslang_input_t input{};
    input.language = GLSLANG_SOURCE_GLSL;
    input.stage = fragment ? GLSLANG_STAGE_FRAGMENT : GLSLANG_STAGE_VERTEX;
    input.code = text.c_str();
    input.default_version = version;
    input.default_profile = profile;
    input.messages = GLSLANG_MSG_DEFAULT_BIT;
    input.resource = glslang_default_resource();
    return input;
}

// GLSL 4.50 -> SPIR-V 1.0 for Vulkan 1.0 (see the header for bindings and locations). Errors are
// given as the renderer gives a driver's (compile_error: file and line of the first error).
std::vector<std::uint32_t> compile_spirv(const ShaderSources& sources, const std::string& file,
                                         const ResolvedSource& resolved, bool fragment) {
    glslang_input_t input = glslang_input(resolved.text, fragment, 450, GLSLANG_CORE_PROFILE);
    input.client = GLSLANG_CLIENT_VULKAN;
    input.client_version = GLSLANG_TARGET_VULKAN_1_0;
    input.target_language = GLSLANG_TARGET_SPV;
    input.target_language_version = GLSLANG_TARGET_SPV_1_0;
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

// SPIR-V as an engine takes it: SPIRV-Tools' performance passes (those of `spirv-opt -O`:
// inlining, constant folding, dead branches, code and variables removed), so that a variant's
// module declares only the resources it reads, then validated for Vulkan 1.0. Deterministic: the
// same module in, the same module out.
std::vector<std::uint32_t> optimise_spirv(const std::string& file,
                                          const std::vector<std::uint32_t>& words) {
    std::string messages;
    auto consumer = [&messages](spv_message_level_t level, const char*,
                                const spv_position_t& position, const char* message) {
        if (level > SPV_MSG_ERROR) return;  // warnings and information
        messages += (messages.empty() ? "" : "; ") + std::string("word ") +
                    std::to_string(position.index) + ": " + (message != nullptr ? message : "");
    };
    spvtools::Optimizer optimizer(SPV_ENV_VULKAN_1_0);
    optimizer.SetMessageConsumer(consumer);
    optimizer.RegisterPerformancePasses();
    std::vector<std::uint32_t> optimised;
    if (!optimizer.Run(words.data(), words.size(), &optimised) || optimised.empty())
        throw Error(file, "SPIRV-Tools cannot optimise the SPIR-V: " +
                              (messages.empty() ? std::string("no message") : messages));
    spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_0);
    tools.SetMessageConsumer(consumer);
    if (!tools.Validate(optimised))
        throw Error(file, "the optimised SPIR-V does not validate for Vulkan 1.0: " +
                              (messages.empty() ? std::string("no message") : messages));
    return optimised;
}

struct ContextDeleter {
    void operator()(spvc_context_s* c) const { spvc_context_destroy(c); }
};

// A SPIRV-Cross context holding one module's parsed IR and a compiler for `backend`; fail(what)
// is the Error naming the file, what failed and SPIRV-Cross's last message. Shared by the
// translation and the reflection.
struct SpirvCross {
    std::unique_ptr<spvc_context_s, ContextDeleter> context;
    spvc_compiler compiler = nullptr;
    std::string file;

    SpirvCross(const std::vector<std::uint32_t>& words, const std::string& file_name,
               spvc_backend backend)
        : file(file_name) {
        spvc_context raw = nullptr;
        if (spvc_context_create(&raw) != SPVC_SUCCESS) throw Error(file, "SPIRV-Cross: no context");
        context.reset(raw);
        spvc_parsed_ir ir = nullptr;
        if (spvc_context_parse_spirv(context.get(), words.data(), words.size(), &ir) !=
            SPVC_SUCCESS)
            throw fail("cannot parse the SPIR-V");
        if (spvc_context_create_compiler(context.get(), backend, ir,
                                         SPVC_CAPTURE_MODE_TAKE_OWNERSHIP,
                                         &compiler) != SPVC_SUCCESS)
            throw fail("has no compiler");
    }
    Error fail(const char* what) const {
        return Error(file, std::string("SPIRV-Cross ") + what + ": " +
                               one_line(spvc_context_get_last_error_string(context.get())));
    }
};

// The resources of `type` in SPIRV-Cross's `resources` (copied out of its context).
template <typename Fail>
std::vector<spvc_reflected_resource> resource_list(spvc_resources resources,
                                                   spvc_resource_type type, const Fail& fail) {
    const spvc_reflected_resource* items = nullptr;
    std::size_t count = 0;
    if (spvc_resources_get_resource_list_for_type(resources, type, &items, &count) != SPVC_SUCCESS)
        throw fail("cannot list the resources");
    return std::vector<spvc_reflected_resource>(items, items + count);
}

// Every resource the module declares.
template <typename Fail>
spvc_resources declared_resources(spvc_compiler compiler, const Fail& fail) {
    spvc_resources resources = nullptr;
    if (spvc_compiler_create_shader_resources(compiler, &resources) != SPVC_SUCCESS)
        throw fail("cannot list the resources");
    return resources;
}

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
    const spvc_resources resources = declared_resources(compiler, fail);
    const SpvExecutionModel model = spvc_compiler_get_execution_model(compiler);
    for (const spvc_resource_type type :
         {SPVC_RESOURCE_TYPE_UNIFORM_BUFFER, SPVC_RESOURCE_TYPE_SAMPLED_IMAGE}) {
        const std::vector<spvc_reflected_resource> list = resource_list(resources, type, fail);
        for (std::size_t i = 0; i < list.size(); ++i) {
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

// GLSL ES 3.00 matches the vertex stage's outputs with the fragment stage's inputs by name, and
// SPIRV-Cross flattens an interface block into <instance>_<member>: the instances (v_out, v_in)
// are given one name in both stages.
constexpr const char* kEsInterfaceName = "lf_vertex";
// The start of the cause of an Error for a stage SPIRV-Cross does not translate.
constexpr const char* kRefusedTranslation = "SPIRV-Cross cannot translate it";

template <typename Fail>
void name_es_interface_blocks(spvc_compiler compiler, const Fail& fail) {
    const spvc_resources resources = declared_resources(compiler, fail);
    for (const spvc_resource_type type :
         {SPVC_RESOURCE_TYPE_STAGE_INPUT, SPVC_RESOURCE_TYPE_STAGE_OUTPUT})
        for (const spvc_reflected_resource& r : resource_list(resources, type, fail)) {
            const spvc_type t = spvc_compiler_get_type_handle(compiler, r.type_id);
            if (spvc_type_get_basetype(t) == SPVC_BASETYPE_STRUCT)
                spvc_compiler_set_name(compiler, r.id, kEsInterfaceName);
        }
}

// glslang's verdict on a GLSL ES 3.00 stage (OpenGL ES rules, as WebGL2's compilers apply them):
// "" when it compiles, else its log as one line.
std::string check_glsl_es(const std::string& text, bool fragment) {
    glslang_input_t input = glslang_input(text, fragment, 300, GLSLANG_ES_PROFILE);
    input.client = GLSLANG_CLIENT_NONE;  // parse and check only: no SPIR-V
    input.target_language = GLSLANG_TARGET_NONE;
    std::unique_ptr<glslang_shader_t, ShaderDeleter> shader(glslang_shader_create(&input));
    if (!shader) return "glslang could not create a shader";
    if (!glslang_shader_preprocess(shader.get(), &input) ||
        !glslang_shader_parse(shader.get(), &input))
        return one_line(glslang_shader_get_info_log(shader.get()));
    return "";
}

// SPIR-V -> HLSL 5.0, MSL or GLSL ES 3.00 by SPIRV-Cross; for SPIR-V itself, only the check of
// its bindings (returns "").
std::string cross_compile(const std::string& file, const std::vector<std::uint32_t>& words,
                          ShaderLanguage language) {
    const spvc_backend backend = language == ShaderLanguage::Hlsl     ? SPVC_BACKEND_HLSL
                                 : language == ShaderLanguage::Msl    ? SPVC_BACKEND_MSL
                                 : language == ShaderLanguage::GlslEs ? SPVC_BACKEND_GLSL
                                                                      : SPVC_BACKEND_NONE;
    const SpirvCross cross(words, file, backend);
    const spvc_compiler compiler = cross.compiler;
    auto fail = [&](const char* what) { return cross.fail(what); };
    bind_resources(compiler, language, file, fail);
    if (backend == SPVC_BACKEND_NONE) return {};
    spvc_compiler_options options = nullptr;
    if (spvc_compiler_create_compiler_options(compiler, &options) != SPVC_SUCCESS)
        throw fail("has no options");
    if (language == ShaderLanguage::Hlsl) {
        spvc_compiler_options_set_uint(options, SPVC_COMPILER_OPTION_HLSL_SHADER_MODEL, 50);
    } else if (language == ShaderLanguage::GlslEs) {
        spvc_compiler_options_set_uint(options, SPVC_COMPILER_OPTION_GLSL_VERSION, 300);
        spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_ES, SPVC_TRUE);
        // The renderer computes in 32-bit floats and ints: highp unless said otherwise.
        spvc_compiler_options_set_bool(
            options, SPVC_COMPILER_OPTION_GLSL_ES_DEFAULT_FLOAT_PRECISION_HIGHP, SPVC_TRUE);
        spvc_compiler_options_set_bool(
            options, SPVC_COMPILER_OPTION_GLSL_ES_DEFAULT_INT_PRECISION_HIGHP, SPVC_TRUE);
        name_es_interface_blocks(compiler, fail);
    } else  // arrays of textures (bump layers) need MSL 2.0, textureQueryLod 2.2
        spvc_compiler_options_set_uint(options, SPVC_COMPILER_OPTION_MSL_VERSION,
                                       SPVC_MAKE_MSL_VERSION(2, 2, 0));
    spvc_compiler_install_compiler_options(compiler, options);
    const char* result = nullptr;
    if (spvc_compiler_compile(compiler, &result) != SPVC_SUCCESS || result == nullptr)
        throw fail(kRefusedTranslation + std::strlen("SPIRV-Cross "));
    return language == ShaderLanguage::Hlsl ? fix_hlsl_lod_queries(result) : std::string(result);
}

// ---- Reflection (SPIRV-Cross) ----

// The GLSL name of a scalar, vector or matrix type ("" for another).
std::string glsl_type_name(spvc_type type) {
    const spvc_basetype base = spvc_type_get_basetype(type);
    const unsigned rows = spvc_type_get_vector_size(type);
    const unsigned columns = spvc_type_get_columns(type);
    std::string prefix;
    std::string scalar;
    switch (base) {
        case SPVC_BASETYPE_FP32:
            scalar = "float";
            break;
        case SPVC_BASETYPE_INT32:
            scalar = "int";
            prefix = "i";
            break;
        case SPVC_BASETYPE_UINT32:
            scalar = "uint";
            prefix = "u";
            break;
        case SPVC_BASETYPE_BOOLEAN:
            scalar = "bool";
            prefix = "b";
            break;
        default:
            return "";
    }
    if (columns > 1) {
        if (base != SPVC_BASETYPE_FP32) return "";
        return columns == rows ? "mat" + std::to_string(columns)
                               : "mat" + std::to_string(columns) + "x" + std::to_string(rows);
    }
    return rows > 1 ? prefix + "vec" + std::to_string(rows) : scalar;
}

// The Vulkan format of a vertex attribute of a 32-bit scalar or vector type ("" for another).
std::string vertex_format(spvc_type type) {
    const unsigned rows = spvc_type_get_vector_size(type);
    if (spvc_type_get_columns(type) > 1 || rows < 1 || rows > 4) return "";
    const char* suffix = nullptr;
    switch (spvc_type_get_basetype(type)) {
        case SPVC_BASETYPE_FP32:
            suffix = "_SFLOAT";
            break;
        case SPVC_BASETYPE_INT32:
            suffix = "_SINT";
            break;
        case SPVC_BASETYPE_UINT32:
            suffix = "_UINT";
            break;
        default:
            return "";
    }
    static const char* const channels[] = {"R32", "R32G32", "R32G32B32", "R32G32B32A32"};
    return std::string(channels[rows - 1]) + suffix;
}

// The elements of an array type with one literal dimension (1 for a type that is not an array,
// 0 for another).
unsigned array_elements(spvc_type type) {
    const unsigned dimensions = spvc_type_get_num_array_dimensions(type);
    if (dimensions == 0) return 1;
    if (dimensions != 1 || !spvc_type_array_dimension_is_literal(type, 0)) return 0;
    return unsigned(spvc_type_get_array_dimension(type, 0));
}

class Reflector {
  public:
    Reflector(spvc_compiler compiler, const std::string& file) : compiler_(compiler), file_(file) {}

    // The members of a block of struct type `struct_id`, nested structs flattened, at `base`.
    void block_members(spvc_type_id struct_id, const std::string& prefix, std::uint32_t base,
                       std::vector<ShaderBlockMember>& out) const {
        const spvc_type type = spvc_compiler_get_type_handle(compiler_, struct_id);
        const unsigned count = spvc_type_get_num_member_types(type);
        for (unsigned i = 0; i < count; ++i) {
            const spvc_type_id member_id = spvc_type_get_member_type(type, i);
            const spvc_type member = spvc_compiler_get_type_handle(compiler_, member_id);
            const char* raw_name = spvc_compiler_get_member_name(compiler_, struct_id, i);
            const std::string name =
                prefix + (raw_name != nullptr && *raw_name != '\0' ? std::string(raw_name)
                                                                   : "_m" + std::to_string(i));
            unsigned offset = 0;
            size_t size = 0;
            check(spvc_compiler_type_struct_member_offset(compiler_, type, i, &offset),
                  "has no member offset");
            check(spvc_compiler_get_declared_struct_member_size(compiler_, type, i, &size),
                  "has no member size");
            const unsigned elements = array_elements(member);
            const bool array = spvc_type_get_num_array_dimensions(member) > 0;
            if (spvc_type_get_basetype(member) == SPVC_BASETYPE_STRUCT && !array) {
                block_members(spvc_type_get_base_type_id(member), name + ".", base + offset, out);
                continue;
            }
            ShaderBlockMember m;
            m.name = name;
            m.type = spvc_type_get_basetype(member) == SPVC_BASETYPE_STRUCT
                         ? std::string(spvc_compiler_get_name(compiler_,
                                                              spvc_type_get_base_type_id(member)))
                         : glsl_type_name(member);
            m.offset = base + offset;
            m.size = std::uint32_t(size);
            if (array) {
                m.array_size = elements;
                unsigned stride = 0;
                check(spvc_compiler_type_struct_member_array_stride(compiler_, type, i, &stride),
                      "has no array stride");
                m.array_stride = stride;
            }
            if (spvc_type_get_columns(member) > 1) {
                unsigned stride = 0;
                check(spvc_compiler_type_struct_member_matrix_stride(compiler_, type, i, &stride),
                      "has no matrix stride");
                m.matrix_stride = stride;
            }
            out.push_back(std::move(m));
        }
    }

    ShaderResource resource(const spvc_reflected_resource& r, bool block) const {
        ShaderResource out = located(r, block ? "uniform_buffer" : "combined_image_sampler");
        if (block) {
            const spvc_type base = spvc_compiler_get_type_handle(compiler_, r.base_type_id);
            size_t size = 0;
            check(spvc_compiler_get_declared_struct_size(compiler_, base, &size),
                  "has no block size");
            out.type = out.name;
            out.block_size = std::uint32_t(size);
            block_members(r.base_type_id, "", 0, out.members);
        } else {
            out.type = image_type_name(r, false);
        }
        return out;
    }

    // A texture or a sampler of a module whose combined samplers were split (WGSL's types).
    ShaderResource separate(const spvc_reflected_resource& r, bool sampler) const {
        ShaderResource out = located(r, sampler ? "sampler" : "sampled_texture");
        out.type = sampler ? "sampler" : image_type_name(r, true);
        return out;
    }

    // The resource's name, descriptor type, set, binding and array size.
    ShaderResource located(const spvc_reflected_resource& r, const char* descriptor_type) const {
        ShaderResource out;
        out.name = r.name != nullptr ? r.name : "";
        out.descriptor_type = descriptor_type;
        out.set = spvc_compiler_get_decoration(compiler_, r.id, SpvDecorationDescriptorSet);
        out.binding = spvc_compiler_get_decoration(compiler_, r.id, SpvDecorationBinding);
        out.array_size = array_elements(spvc_compiler_get_type_handle(compiler_, r.type_id));
        return out;
    }

    // A texture's type: GLSL's sampler ("sampler2DArray") or WGSL's ("texture_2d_array<f32>").
    std::string image_type_name(const spvc_reflected_resource& r, bool wgsl) const {
        const spvc_type image = spvc_compiler_get_type_handle(compiler_, r.base_type_id);
        const bool arrayed = spvc_type_get_image_arrayed(image);
        const char* glsl = "sampler2D";
        const char* wgsl_name = "texture_2d";
        switch (spvc_type_get_image_dimension(image)) {
            case SpvDim1D: glsl = "sampler1D", wgsl_name = "texture_1d"; break;
            case SpvDim3D: glsl = "sampler3D", wgsl_name = "texture_3d"; break;
            case SpvDimCube: glsl = "samplerCube", wgsl_name = "texture_cube"; break;
            default: break;
        }
        if (wgsl) return std::string(wgsl_name) + (arrayed ? "_array<f32>" : "<f32>");
        return std::string(glsl) + (arrayed ? "Array" : "");
    }

    // A stage input or output: a variable, or a block's members at consecutive locations (each
    // scalar, vector or matrix column takes one). Built-ins are left out.
    void interface_variable(const spvc_reflected_resource& r,
                            std::vector<ShaderInterfaceVariable>& out) const {
        if (spvc_compiler_has_decoration(compiler_, r.id, SpvDecorationBuiltIn)) return;
        const std::uint32_t location =
            spvc_compiler_get_decoration(compiler_, r.id, SpvDecorationLocation);
        const spvc_type type = spvc_compiler_get_type_handle(compiler_, r.type_id);
        if (spvc_type_get_basetype(type) != SPVC_BASETYPE_STRUCT) {
            out.push_back({r.name != nullptr ? r.name : "", location, glsl_type_name(type),
                           vertex_format(type)});
            return;
        }
        const spvc_type_id struct_id = r.base_type_id;
        const spvc_type block = spvc_compiler_get_type_handle(compiler_, struct_id);
        const std::string block_name = spvc_compiler_get_name(compiler_, struct_id);
        std::uint32_t next = location;
        for (unsigned i = 0; i < spvc_type_get_num_member_types(block); ++i) {
            if (spvc_compiler_has_member_decoration(compiler_, struct_id, i, SpvDecorationBuiltIn))
                continue;
            const spvc_type member =
                spvc_compiler_get_type_handle(compiler_, spvc_type_get_member_type(block, i));
            if (spvc_compiler_has_member_decoration(compiler_, struct_id, i, SpvDecorationLocation))
                next = spvc_compiler_get_member_decoration(compiler_, struct_id, i,
                                                           SpvDecorationLocation);
            out.push_back(
                {block_name + "." + spvc_compiler_get_member_name(compiler_, struct_id, i), next,
                 glsl_type_name(member), vertex_format(member)});
            next +=
                std::max(1u, spvc_type_get_columns(member)) * std::max(1u, array_elements(member));
        }
    }

  private:
    void check(spvc_result result, const char* what) const {
        if (result != SPVC_SUCCESS)
            throw Error(file_, std::string("SPIRV-Cross: the block ") + what);
    }
    spvc_compiler compiler_;
    const std::string& file_;
};

}  // namespace

ShaderReflection reflect_spirv(const std::vector<std::uint32_t>& words, const std::string& file) {
    const SpirvCross cross(words, file, SPVC_BACKEND_NONE);
    const spvc_compiler compiler = cross.compiler;
    auto fail = [&](const char* what) { return cross.fail(what); };
    // Only what the entry point uses: a resource declared and never read is no descriptor.
    spvc_set active = nullptr;
    spvc_resources resources = nullptr;
    if (spvc_compiler_get_active_interface_variables(compiler, &active) != SPVC_SUCCESS ||
        spvc_compiler_create_shader_resources_for_active_variables(compiler, &resources, active) !=
            SPVC_SUCCESS)
        throw fail("cannot list the resources");
    auto list = [&](spvc_resource_type type) { return resource_list(resources, type, fail); };

    ShaderReflection out;
    const SpvExecutionModel model = spvc_compiler_get_execution_model(compiler);
    out.stage = model == SpvExecutionModelVertex     ? "vertex"
                : model == SpvExecutionModelFragment ? "fragment"
                                                     : "other";
    const spvc_entry_point* entry_points = nullptr;
    std::size_t entry_count = 0;
    if (spvc_compiler_get_entry_points(compiler, &entry_points, &entry_count) != SPVC_SUCCESS ||
        entry_count == 0)
        throw fail("finds no entry point");
    out.entry_point = entry_points[0].name;

    const Reflector reflector(compiler, file);
    for (const spvc_reflected_resource& r : list(SPVC_RESOURCE_TYPE_UNIFORM_BUFFER))
        out.resources.push_back(reflector.resource(r, true));
    for (const spvc_reflected_resource& r : list(SPVC_RESOURCE_TYPE_SAMPLED_IMAGE))
        out.resources.push_back(reflector.resource(r, false));
    // Split samplers (WGSL's): textures and samplers apart.
    for (const spvc_reflected_resource& r : list(SPVC_RESOURCE_TYPE_SEPARATE_IMAGE))
        out.resources.push_back(reflector.separate(r, false));
    for (const spvc_reflected_resource& r : list(SPVC_RESOURCE_TYPE_SEPARATE_SAMPLERS))
        out.resources.push_back(reflector.separate(r, true));
    // Resources of other kinds would need descriptors this reflection does not describe.
    for (const spvc_resource_type other :
         {SPVC_RESOURCE_TYPE_STORAGE_BUFFER, SPVC_RESOURCE_TYPE_STORAGE_IMAGE,
          SPVC_RESOURCE_TYPE_PUSH_CONSTANT, SPVC_RESOURCE_TYPE_SUBPASS_INPUT})
        if (!list(other).empty())
            throw Error(file,
                        "the module has a resource of a kind that leanfade does not reflect "
                        "(only uniform blocks, textures and samplers)");
    std::sort(out.resources.begin(), out.resources.end(),
              [](const ShaderResource& a, const ShaderResource& b) {
                  return std::tie(a.set, a.binding) < std::tie(b.set, b.binding);
              });
    for (const spvc_reflected_resource& r : list(SPVC_RESOURCE_TYPE_STAGE_INPUT))
        reflector.interface_variable(r, out.inputs);
    for (const spvc_reflected_resource& r : list(SPVC_RESOURCE_TYPE_STAGE_OUTPUT))
        reflector.interface_variable(r, out.outputs);
    for (auto* variables : {&out.inputs, &out.outputs})
        std::stable_sort(variables->begin(), variables->end(),
                         [](const ShaderInterfaceVariable& a, const ShaderInterfaceVariable& b) {
                             return a.location < b.location;
                         });
    return out;
}

namespace {

std::vector<std::uint8_t> text_bytes(const std::string& text) {
    return std::vector<std::uint8_t>(text.begin(), text.end());
}

std::vector<std::uint8_t> spirv_bytes(const std::vector<std::uint32_t>& words) {
    std::vector<std::uint8_t> bytes;
    bytes.reserve(words.size() * 4);
    for (const std::uint32_t w : words)
        for (int shift = 0; shift < 32; shift += 8) bytes.push_back(std::uint8_t(w >> shift));
    return bytes;
}

std::vector<std::uint32_t> spirv_words(const std::vector<std::uint8_t>& bytes) {
    std::vector<std::uint32_t> words(bytes.size() / 4, 0u);
    for (std::size_t i = 0; i < words.size() * 4; ++i)
        words[i / 4] |= std::uint32_t(bytes[i]) << (8 * (i % 4));
    return words;
}

ExportedShader export_stage(const ShaderSources& sources, const ShaderVariant* variant,
                            ShaderLanguage language) {
    const bool fragment = variant != nullptr;
    ExportedShader out;
    out.variant = fragment ? variant->name : "scene";
    out.stage = fragment ? "frag" : "vert";
    out.source = fragment ? kFragmentFile : kVertexFile;
    if (fragment) out.defines = variant->defines;
    if (language == ShaderLanguage::Wgsl) out.defines.push_back("LF_SEPARATE_VARYINGS");
    out.file_name = out.variant + "." + out.stage + file_extension(language);
    const ResolvedSource resolved = sources.resolve(out.source, out.defines);
    if (language == ShaderLanguage::Glsl) {
        out.bytes = text_bytes(standalone_glsl(resolved, variant));
        return out;
    }
    const std::vector<std::uint32_t> words = compile_spirv(sources, out.source, resolved, fragment);
    if (language == ShaderLanguage::Spirv) {
        cross_compile(out.source, words, language);  // checks the bindings
        const std::vector<std::uint32_t> optimised = optimise_spirv(out.source, words);
        out.unoptimised_size = words.size() * 4;
        out.reflection = reflect_spirv(optimised, out.source);
        out.bytes = spirv_bytes(optimised);
        return out;
    }
    if (language == ShaderLanguage::GlslEs) {
        // What ES 3.00 cannot express is an omission with its reason, not an error: SPIRV-Cross
        // refuses a construct (a LOD query), or glslang the translation (a sampler array indexed
        // with a variable).
        out.reflection = reflect_spirv(words, out.source);
        for (ShaderResource& r : out.reflection.resources)
            if (r.descriptor_type == "uniform_buffer") r.binding -= kSpirvUniformBlockBase;
        std::string text;
        try {
            text = cross_compile(out.source, words, language);
        } catch (const Error& e) {
            if (e.cause().rfind(kRefusedTranslation, 0) != 0) throw;
            out.omitted = e.cause();
            return out;
        }
        const std::string verdict = check_glsl_es(text, fragment);
        if (!verdict.empty()) {
            out.omitted = "not GLSL ES 3.00: " + verdict;
            return out;
        }
        out.bytes = text_bytes(text);
        return out;
    }
    if (language == ShaderLanguage::Wgsl) {
        // The module as SPIR-V exports it, its samplers split; the text comes from naga
        // (export_shaders translates every module in one run).
        cross_compile(out.source, words, ShaderLanguage::Spirv);  // checks the bindings
        const SplitSamplers split =
            split_combined_image_samplers(optimise_spirv(out.source, words), kWgslSamplerBindingOffset);
        if (!split.refused.empty()) {
            out.omitted = "no WGSL form: " + split.refused;
            return out;
        }
        spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_0);
        std::string messages;
        tools.SetMessageConsumer([&messages](spv_message_level_t, const char*,
                                             const spv_position_t&, const char* message) {
            if (messages.empty()) messages = message;
        });
        if (!tools.Validate(split.words))
            throw Error(out.source, "the SPIR-V with split samplers does not validate: " +
                                        one_line(messages.c_str()));
        out.reflection = reflect_spirv(split.words, out.source);
        out.bytes = spirv_bytes(split.words);
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
    static const std::vector<std::string> names{"glsl", "spirv", "hlsl", "msl", "glsl-es",
                                                "wgsl"};
    return names;
}

ShaderLanguage parse_shader_language(std::string_view name, const std::string& setting) {
    const std::vector<std::string>& names = shader_language_names();
    for (std::size_t i = 0; i < names.size(); ++i)
        if (name == names[i]) return ShaderLanguage(i);
    throw Error::setting(setting, "unknown shader language '" + escape_text(std::string(name)) +
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
        case ShaderLanguage::GlslEs:
            return ".essl";
        case ShaderLanguage::Wgsl:
            return ".wgsl";
    }
    return "";
}

std::vector<ExportedShader> export_shaders(const ShaderSources& sources, ShaderLanguage language,
                                           const std::string& wgsl_translator) {
    if (language == ShaderLanguage::Wgsl && wgsl_translator.empty())
        throw Error::setting(
            "lang",
            "WGSL is translated by naga (npm package naga-wasm, run by Node.js), and no "
            "translator was found beside the program (share/leanfade/node; "
            "scripts/install-deps.sh installs it)");
    std::vector<ExportedShader> shaders;
    shaders.push_back(export_stage(sources, nullptr, language));
    for (const ShaderVariant& variant : shader_variants())
        if (variant.vertex == kVertexFile && variant.fragment == kFragmentFile)
            shaders.push_back(export_stage(sources, &variant, language));
    if (language == ShaderLanguage::Wgsl) {
        std::vector<std::vector<std::uint32_t>> modules;
        std::vector<std::string> names;
        for (const ExportedShader& s : shaders)
            if (s.omitted.empty()) {
                modules.push_back(spirv_words(s.bytes));
                names.push_back(s.file_name);
            }
        const std::vector<WgslTranslation> texts =
            translate_spirv_to_wgsl(modules, names, wgsl_translator);
        std::size_t next = 0;
        for (ExportedShader& s : shaders) {
            if (!s.omitted.empty()) continue;
            const WgslTranslation& t = texts[next++];
            if (t.refused.empty()) {
                s.bytes = text_bytes(t.text);
            } else {
                s.bytes.clear();
                s.omitted = "naga refuses the translation: " + t.refused;
            }
        }
    }
    return shaders;
}

}  // namespace leanfade::gl
