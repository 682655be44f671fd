// Shader source resolution (#include, variant #defines) and program building.
#include "leanfade/gl/shader_library.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"

namespace leanfade::embedded {
const std::map<std::string, std::string_view>& shader_files();
}  // namespace leanfade::embedded

namespace leanfade::gl {
namespace {

constexpr int kMaxIncludeDepth = 16;
// Largest shader file of a --shader-dir folder, and largest source once its includes are resolved.
constexpr std::uint64_t kMaxShaderFileBytes = std::uint64_t(1) << 20;
constexpr std::size_t kMaxResolvedShaderBytes = std::size_t(4) << 20;

bool starts_with_directive(const std::string& line, const std::string& directive,
                           std::string* rest) {
    std::size_t i = line.find_first_not_of(" \t");
    if (i == std::string::npos || line[i] != '#') return false;
    i = line.find_first_not_of(" \t", i + 1);
    if (i == std::string::npos || line.compare(i, directive.size(), directive) != 0) return false;
    const std::size_t after = i + directive.size();
    if (after < line.size() && line[after] != ' ' && line[after] != '\t') return false;
    if (rest != nullptr) *rest = line.substr(after);
    return true;
}

std::string trim(const std::string& s) {
    const std::size_t a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return {};
    const std::size_t b = s.find_last_not_of(" \t\r");
    return s.substr(a, b - a + 1);
}

struct Resolver {
    std::function<std::string(const std::string&)> read;
    ResolvedSource out;

    // Appends the text of `name` to out.text; `defines` is given for the main file only.
    void append(const std::string& name, const std::string& text, int depth,
                const std::vector<std::string>* defines) {
        const int index =
            int(std::find(out.files.begin(), out.files.end(), name) - out.files.begin());
        std::istringstream in(text);
        std::string line;
        int line_number = 0;
        bool version_seen = false;
        while (std::getline(in, line)) {
            ++line_number;
            std::string rest;
            if (defines != nullptr && !version_seen) {
                // The main file: #version first, then the variant's defines.
                if (!starts_with_directive(line, "version", nullptr))
                    throw Error(name, "the first line must be #version");
                version_seen = true;
                out.text += line + "\n";
                for (const std::string& d : *defines) out.text += "#define " + d + "\n";
                out.text +=
                    "#line " + std::to_string(line_number + 1) + " " + std::to_string(index) + "\n";
                continue;
            }
            if (starts_with_directive(line, "include", &rest)) {
                const std::string target = trim(rest);
                if (target.size() < 3 || target.front() != '"' || target.back() != '"')
                    throw Error(name, "line " + std::to_string(line_number) +
                                          ": expected #include \"file\"");
                const std::string included = target.substr(1, target.size() - 2);
                if (std::find(out.files.begin(), out.files.end(), included) == out.files.end()) {
                    if (depth >= kMaxIncludeDepth)
                        throw Error(name, "includes nested deeper than " +
                                              std::to_string(kMaxIncludeDepth) + " levels");
                    out.files.push_back(included);
                    const int child = int(out.files.size()) - 1;
                    out.text += "#line 1 " + std::to_string(child) + "\n";
                    append(included, read(included), depth + 1, nullptr);
                }
                out.text +=
                    "#line " + std::to_string(line_number + 1) + " " + std::to_string(index) + "\n";
                continue;
            }
            out.text += line + "\n";
            if (out.text.size() > kMaxResolvedShaderBytes)
                throw Error(name, "the shader source with its includes exceeds " +
                                      std::to_string(kMaxResolvedShaderBytes) + " bytes");
            // An #include inside a block the preprocessor skips leaves its #line directives
            // unread: where such a block can end, the line number is stated again.
            if (starts_with_directive(line, "endif", nullptr) ||
                starts_with_directive(line, "else", nullptr) ||
                starts_with_directive(line, "elif", nullptr))
                out.text += "#line " + std::to_string(line_number + 1) + " " +
                            std::to_string(index) + "\n";
        }
        if (defines != nullptr && !version_seen) throw Error(name, "the file is empty");
    }
};

std::string stage_log(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(std::size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    return log;
}

std::string one_line(std::string text) {
    std::replace(text.begin(), text.end(), '\n', ' ');
    return trim(text);
}

const char* stage_name(GLenum stage) {
    switch (stage) {
        case GL_VERTEX_SHADER:
            return "vertex";
        case GL_FRAGMENT_SHADER:
            return "fragment";
        case GL_COMPUTE_SHADER:
            return "compute";
        default:
            return "shader";
    }
}

// Reads an unsigned decimal number at text[i], advancing i; false when there is none.
bool read_number(const std::string& text, std::size_t& i, long& value) {
    const std::size_t start = i;
    value = 0;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9' && i - start < 9)
        value = value * 10 + (text[i++] - '0');
    return i > start;
}

// One line of a driver's info log, with the location taken apart when it has one.
struct LogEntry {
    bool located = false;
    long string = 0;  // source string number (#line's second argument)
    long line = 0;
    long column = 0;  // 0: not given
    std::string message;
};

// Understands the location formats of the common drivers:
//   Mesa                "0:12(5): error: ..."
//   NVIDIA              "0(12) : error C1008: ..."
//   AMD, Intel, glslang "ERROR: 0:12: ..."
LogEntry parse_log_line(const std::string& raw) {
    LogEntry e;
    const std::string line = trim(raw);
    e.message = line;
    std::size_t i = 0;
    std::string severity;
    for (const char* prefix : {"ERROR: ", "WARNING: "}) {
        if (line.rfind(prefix, 0) == 0) {
            severity = std::string(prefix) == "ERROR: " ? "error: " : "warning: ";
            i = std::strlen(prefix);
        }
    }
    long a = 0, b = 0, c = 0;
    if (!read_number(line, i, a)) return e;
    if (i < line.size() && line[i] == ':') {
        ++i;
        if (!read_number(line, i, b)) return e;
        if (i < line.size() && line[i] == '(') {
            ++i;
            if (!read_number(line, i, c) || i >= line.size() || line[i] != ')') return e;
            ++i;
        }
    } else if (i < line.size() && line[i] == '(') {
        ++i;
        if (!read_number(line, i, b) || i >= line.size() || line[i] != ')') return e;
        ++i;
    } else {
        return e;
    }
    while (i < line.size() && line[i] == ' ') ++i;
    if (i >= line.size() || line[i] != ':') return e;
    ++i;
    e.located = true;
    e.string = a;
    e.line = b;
    e.column = c;
    e.message = severity + trim(line.substr(i));
    return e;
}

bool is_error(const LogEntry& e) {
    return e.message.rfind("warning", 0) != 0 && e.message.find("error") != std::string::npos;
}

}  // namespace

Error compile_error(GLenum stage, const std::string& name, const ResolvedSource& source,
                    const ShaderSources& sources, const std::string& log) {
    auto file_of = [&](const LogEntry& e) -> std::string {
        if (e.string >= 0 && std::size_t(e.string) < source.files.size())
            return sources.location(source.files[std::size_t(e.string)]);
        return "source string " + std::to_string(e.string);
    };
    auto where = [](const LogEntry& e) {
        std::string w = "line " + std::to_string(e.line);
        if (e.column > 0) w += ", column " + std::to_string(e.column);
        return w;
    };
    std::vector<LogEntry> entries;
    std::istringstream in(log);
    std::string raw;
    while (std::getline(in, raw))
        if (!trim(raw).empty()) entries.push_back(parse_log_line(raw));

    // The first located error names the file; the others follow, with their own files.
    const LogEntry* first = nullptr;
    for (const LogEntry& e : entries)
        if (e.located && is_error(e)) {
            first = &e;
            break;
        }
    if (first == nullptr)
        for (const LogEntry& e : entries)
            if (e.located) {
                first = &e;
                break;
            }
    const std::string file = first != nullptr ? file_of(*first) : sources.location(name);
    std::string cause = first != nullptr ? where(*first) + ": " + first->message : "";
    for (const LogEntry& e : entries) {
        if (&e == first) continue;
        std::string text = e.message;
        if (e.located) {
            const std::string f = file_of(e);
            text = (f == file ? "" : f + " ") + where(e) + ": " + e.message;
        }
        cause += (cause.empty() ? "" : "; ") + text;
    }
    if (cause.empty()) cause = "the driver gave no log";
    const std::string stage_text = std::string(stage_name(stage)) + " shader " + name;
    cause += file == sources.location(name)
                 ? " (the " + stage_text + " does not compile)"
                 : " (included by the " + stage_text + ", which does not compile)";
    return Error(file, one_line(cause));
}

namespace {

Shader compile_stage(GLenum stage, const std::string& name, const ResolvedSource& source,
                     const ShaderSources& sources) {
    Shader shader(glCreateShader(stage));
    const char* text = source.text.c_str();
    glShaderSource(shader.get(), 1, &text, nullptr);
    glCompileShader(shader.get());
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.get(), GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) throw compile_error(stage, name, source, sources, stage_log(shader.get()));
    return shader;
}

}  // namespace

ShaderSources ShaderSources::embedded() {
    ShaderSources s;
    s.origin_ = "embedded";
    return s;
}

ShaderSources ShaderSources::directory(const std::string& folder) {
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec))
        throw Error(folder, "is not a folder of shader files");
    ShaderSources s;
    s.folder_ = folder;
    s.origin_ = folder;
    return s;
}

std::string ShaderSources::read(const std::string& name) const {
    if (name.find("..") != std::string::npos || name.empty() || name.front() == '/')
        throw Error(name, "shader file names must be relative to the shader folder");
    if (!folder_) {
        const auto& files = embedded::shader_files();
        const auto it = files.find(name);
        if (it == files.end()) throw Error(name, "no such embedded shader file");
        return std::string(it->second);
    }
    const std::string path = (std::filesystem::path(*folder_) / name).string();
    std::error_code error;
    if (!std::filesystem::exists(path, error)) throw Error(path, "cannot read the shader file");
    // Confined on the resolved path too, before any byte is read: a link in the folder to a file
    // outside it is refused (its text would reach the compile log's messages).
    if (!resolves_inside(path, *folder_))
        throw Error(path, "resolves outside the shader folder (through a symbolic link)");
    // A regular file of bounded size only: a FIFO cannot hang the read, a device (a link to
    // /dev/zero) cannot make it grow (docs/robustness.md).
    return read_regular_file(path, kMaxShaderFileBytes, "a shader file");
}

std::string ShaderSources::location(const std::string& name) const {
    if (!folder_) return name;
    return (std::filesystem::path(*folder_) / name).string();
}

ResolvedSource ShaderSources::resolve(const std::string& name,
                                      const std::vector<std::string>& defines) const {
    Resolver r;
    r.read = [this](const std::string& n) { return read(n); };
    r.out.files.push_back(name);
    r.append(name, read(name), 0, &defines);
    return std::move(r.out);
}

std::string variant_name(const VariantKey& key) {
    switch (key.program) {
        case VariantKey::Program::BoxFilter: return "box_filter";
        case VariantKey::Program::ConstantColor: return "scene_constant";
        case VariantKey::Program::Scene: break;
    }
    std::string name = "scene_" + std::string(info(key.technique).name);
    for (const SceneVariantBit& row : kSceneVariantBits)
        if (key.flags & row.bit) name += row.suffix;
    return name;
}

bool uses_geometric_aa(Technique technique, const ShadingSettings& settings) {
    const TechniqueInfo& row = info(technique);
    if (row.supersampled) return false;
    return settings.geometric_aa == GeometricAa::On ||
           (settings.geometric_aa == GeometricAa::Auto && row.geometric_aa_by_default);
}

SceneVariantFlags scene_variant_flags(Technique technique, const ShadingSettings& settings) {
    SceneVariantFlags flags = 0;
    if (settings.brdf == Brdf::CookTorrance) flags |= kCookTorrance;
    if (info(technique).supersampled && settings.reference_model == ReferenceModel::Lean)
        flags |= kLeanModel;
    if (uses_geometric_aa(technique, settings)) flags |= kGeometricAa;
    return flags;
}

bool has_variant(const VariantKey& key) {
    if (!key.is_scene()) return key.flags == 0;
    const TechniqueInfo& row = info(key.technique);
    const SceneVariantFlags flags = key.flags;
    if ((flags & ~kAllSceneVariantFlags) != 0) return false;
    for (const SceneVariantBit& bit : kSceneVariantBits) {
        if ((flags & bit.bit) == 0) continue;
        const bool in_scope = bit.scope == VariantScope::Every ||
                              (bit.scope == VariantScope::NotSupersampled && !row.supersampled) ||
                              (bit.scope == VariantScope::Supersampled && row.supersampled) ||
                              (bit.scope == VariantScope::Fading && row.fades);
        if (!in_scope) return false;
    }
    return true;
}

namespace {

// The defines of a scene variant (shaders/scene.frag, lean_shading.glsl).
std::vector<std::string> scene_defines(const VariantKey& key) {
    const TechniqueInfo& row = info(key.technique);
    const SceneVariantFlags flags = key.flags;
    // LEAN's own model as the truth: LEAN's lobe at the finest level (docs/math.md §7).
    const bool lean_model = (flags & kLeanModel) != 0;
    const int technique = lean_model ? shading::LF_TECHNIQUE_LEAN : row.shader_technique;
    std::vector<std::string> defines{"LF_TECHNIQUE " + std::to_string(technique)};
    defines.push_back("LF_BRDF " + std::to_string((flags & kCookTorrance)
                                                      ? shading::LF_BRDF_COOK_TORRANCE
                                                      : shading::LF_BRDF_BLINN_PHONG));
    if (row.reads_moments || lean_model) defines.push_back("LF_READS_MOMENTS");
    // The engine's textures, filtered in the shader (docs/roughness.md).
    if (technique == shading::LF_TECHNIQUE_ROUGHNESS_MIPS) defines.push_back("LF_ROUGHNESS_MIPS");
    if (row.supersampled) defines.push_back("LF_FINEST_LEVEL_ONLY");
    if (row.reads_plateau) defines.push_back("LF_READS_PLATEAU");
    // The bits' own defines (kSceneVariantBits).
    for (const SceneVariantBit& bit : kSceneVariantBits)
        if (flags & bit.bit)
            for (const std::string_view define : bit.defines)
                if (!define.empty()) defines.emplace_back(define);
    return defines;
}

}  // namespace

const std::vector<ShaderVariant>& shader_variants() {
    static const std::vector<ShaderVariant> variants = [] {
        std::vector<ShaderVariant> result;
        for (const TechniqueInfo& row : kTechniques) {
            for (SceneVariantFlags flags = 0; flags <= kAllSceneVariantFlags; ++flags) {
                const VariantKey key = VariantKey::scene(row.id, flags);
                if (!has_variant(key)) continue;
                result.push_back(
                    {key, variant_name(key), "scene.vert", "scene.frag", scene_defines(key)});
            }
        }
        const VariantKey box = VariantKey::box_filter(), constant = VariantKey::constant_color();
        result.push_back({box, variant_name(box), "fullscreen.vert", "box_filter.frag", {}});
        result.push_back({constant, variant_name(constant), "scene.vert", "constant.frag", {}});
        return result;
    }();
    return variants;
}

const ShaderVariant& shader_variant(const VariantKey& key) {
    for (const ShaderVariant& v : shader_variants())
        if (v.key == key) return v;
    throw Error("shaders", "no shader variant " + variant_name(key));
}

Program build_program(const ShaderSources& sources, const ShaderVariant& variant) {
    const ResolvedSource vertex_source = sources.resolve(variant.vertex, variant.defines);
    const ResolvedSource fragment_source = sources.resolve(variant.fragment, variant.defines);
    Shader vertex = compile_stage(GL_VERTEX_SHADER, variant.vertex, vertex_source, sources);
    Shader fragment = compile_stage(GL_FRAGMENT_SHADER, variant.fragment, fragment_source, sources);
    Program program(glCreateProgram());
    glAttachShader(program.get(), vertex.get());
    glAttachShader(program.get(), fragment.get());
    glLinkProgram(program.get());
    glDetachShader(program.get(), vertex.get());
    glDetachShader(program.get(), fragment.get());
    GLint ok = GL_FALSE;
    glGetProgramiv(program.get(), GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint length = 0;
        glGetProgramiv(program.get(), GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        glGetProgramInfoLog(program.get(), GLsizei(log.size()), nullptr, log.data());
        log.resize(std::strlen(log.c_str()));
        throw Error(variant.vertex + " + " + variant.fragment,
                    "does not link (" + variant.name + "): " + one_line(log));
    }
    return program;
}

Program build_compute_program(const ShaderSources& sources, const std::string& file,
                              const std::vector<std::string>& defines) {
    const ResolvedSource source = sources.resolve(file, defines);
    Shader compute = compile_stage(GL_COMPUTE_SHADER, file, source, sources);
    Program program(glCreateProgram());
    glAttachShader(program.get(), compute.get());
    glLinkProgram(program.get());
    glDetachShader(program.get(), compute.get());
    GLint ok = GL_FALSE;
    glGetProgramiv(program.get(), GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint length = 0;
        glGetProgramiv(program.get(), GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        glGetProgramInfoLog(program.get(), GLsizei(log.size()), nullptr, log.data());
        log.resize(std::strlen(log.c_str()));
        throw Error(file, "does not link: " + one_line(log));
    }
    return program;
}

}  // namespace leanfade::gl
