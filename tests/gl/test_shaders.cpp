// Shader sources: #include resolution, variants, disk folders, glslangValidator and the driver.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <span>
#include <sstream>

#include "gl_test_helpers.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/gl/shader_library.hpp"
#include "leanfade/gl/detail/shading_block.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

void write_file(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

// Runs a command, returning its exit status and its output (stdout and stderr together).
int run(const std::string& command, std::string& output) {
    FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
    if (pipe == nullptr) return -1;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
    const int status = ::pclose(pipe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
    return n;
}

TEST(ShaderSources, EveryVariantPassesGlslangValidator) {
    const std::string validator = LEANFADE_GLSLANG_VALIDATOR;
    ASSERT_FALSE(validator.empty())
        << "glslangValidator was not found at configure time (Debian: apt install glslang-tools)";
    const fs::path dir = scratch_dir("glslang");
    const gl::ShaderSources sources = gl::ShaderSources::embedded();
    for (const gl::ShaderVariant& variant : gl::shader_variants()) {
        for (const std::string& stage : {variant.vertex, variant.fragment}) {
            const gl::ResolvedSource resolved = sources.resolve(stage, variant.defines);
            // glslangValidator infers the stage from the extension (.vert / .frag).
            const fs::path file =
                dir / (variant.name + "." + fs::path(stage).extension().string().substr(1));
            write_file(file, resolved.text);
            std::string output;
            const int status = run("'" + validator + "' '" + file.string() + "'", output);
            EXPECT_EQ(status, 0) << variant.name << " / " << stage << ":\n" << output;
        }
    }
}

// Programs are found by their typed key: every key and every name is built once, the name is
// the key's, and each key finds its own variant.
TEST(ShaderSources, EveryVariantHasItsOwnKeyAndName) {
    std::set<gl::VariantKey> keys;
    std::set<std::string> names;
    for (const gl::ShaderVariant& variant : gl::shader_variants()) {
        EXPECT_TRUE(keys.insert(variant.key).second) << variant.name;
        EXPECT_TRUE(names.insert(variant.name).second) << variant.name;
        EXPECT_EQ(variant.name, gl::variant_name(variant.key));
        EXPECT_TRUE(gl::has_variant(variant.key)) << variant.name;
        EXPECT_EQ(&gl::shader_variant(variant.key), &variant);
    }
    // Every technique of the table has its ordinary and its layered scene program.
    for (const TechniqueInfo& row : kTechniques) {
        EXPECT_EQ(keys.count(gl::VariantKey::scene(row.id)), 1u) << row.name;
        EXPECT_EQ(keys.count(gl::VariantKey::scene(row.id, gl::kLayered)), 1u) << row.name;
    }
    EXPECT_EQ(keys.count(gl::VariantKey::box_filter()), 1u);
    EXPECT_EQ(keys.count(gl::VariantKey::constant_color()), 1u);
}

// The variant bits' table (kSceneVariantBits) gives the names, the scopes and the defines: the
// names as they were before the table, each bit only on the techniques of its scope, and each
// row's defines in the variants with its bit.
TEST(ShaderSources, VariantBitsFollowTheirTable) {
    using gl::VariantKey;
    EXPECT_EQ(gl::variant_name(VariantKey::scene(Technique::Fade, gl::kPlainColor | gl::kFadeFast |
                                                                      gl::kCookTorrance)),
              "scene_fade_plain_fast_ct");
    EXPECT_EQ(gl::variant_name(VariantKey::scene(Technique::TwoLobe, gl::kLayered |
                                                                         gl::kGeometricAa)),
              "scene_two-lobe_layered_gaa");
    EXPECT_EQ(gl::variant_name(VariantKey::scene(Technique::Reference, gl::kLeanModel)),
              "scene_reference_leanmodel");
    EXPECT_EQ(gl::kAllSceneVariantFlags, 63u);
    EXPECT_FALSE(gl::has_variant(VariantKey::scene(Technique::Lean, gl::kFadeFast)));
    EXPECT_FALSE(gl::has_variant(VariantKey::scene(Technique::Reference, gl::kPlainColor)));
    EXPECT_FALSE(gl::has_variant(VariantKey::scene(Technique::Reference, gl::kGeometricAa)));
    EXPECT_FALSE(gl::has_variant(VariantKey::scene(Technique::Lean, gl::kLeanModel)));
    EXPECT_FALSE(gl::has_variant(VariantKey::scene(Technique::Lean, 64u)));
    EXPECT_TRUE(gl::has_variant(VariantKey::scene(Technique::Fade, gl::kFadeFast)));
    for (const gl::ShaderVariant& variant : gl::shader_variants()) {
        if (!variant.key.is_scene()) continue;
        for (const gl::SceneVariantBit& bit : gl::kSceneVariantBits)
            for (const std::string_view define : bit.defines) {
                if (define.empty()) continue;
                const bool has = std::find(variant.defines.begin(), variant.defines.end(),
                                           std::string(define)) != variant.defines.end();
                EXPECT_EQ(has, (variant.key.flags & bit.bit) != 0) << variant.name << " " << define;
            }
    }
}

TEST(ShaderSources, FragmentStageIncludesTheSharedHeaderOnce) {
    const gl::ShaderSources sources = gl::ShaderSources::embedded();
    const gl::ResolvedSource r = sources.resolve("scene.frag", {"LF_TECHNIQUE 1"});
    ASSERT_EQ(r.files.size(), 5u);
    EXPECT_EQ(r.files[0], "scene.frag");
    EXPECT_EQ(r.files[1], "lean_shading.glsl");
    EXPECT_EQ(r.files[2], "bindings.glsl");
    EXPECT_EQ(r.files[3], "map_kinds.glsl");     // generated from kMapKinds
    EXPECT_EQ(r.files[4], "map_samplers.glsl");  // generated from kMapKinds
    EXPECT_EQ(r.text.rfind("#version 450 core\n#define LF_TECHNIQUE 1\n", 0), 0u) << r.text;
    EXPECT_EQ(count(r.text, "LF_FN LfShade lf_shade("), 1u);
    EXPECT_EQ(count(r.text, "#include"), 0u);
}

TEST(ShaderSources, EmbeddedCopiesMatchTheShaderFolder) {
    const gl::ShaderSources embedded = gl::ShaderSources::embedded();
    const gl::ShaderSources disk =
        gl::ShaderSources::directory(std::string(LEANFADE_SOURCE_DIR) + "/shaders");
    for (const gl::ShaderVariant& variant : gl::shader_variants())
        for (const std::string& stage : {variant.vertex, variant.fragment})
            EXPECT_EQ(embedded.resolve(stage, variant.defines).text,
                      disk.resolve(stage, variant.defines).text)
                << stage << ": rebuild to re-embed the shaders";
}

TEST(ShaderSources, ResolvesNestedIncludesOnceWithLineDirectives) {
    const fs::path dir = scratch_dir("includes");
    write_file(dir / "main.frag",
               "#version 450 core\n#include \"a.glsl\"\n  #  include \"b.glsl\"\nvoid main() {}\n");
    write_file(dir / "a.glsl", "// a\n#include \"b.glsl\"\nfloat a() { return b(); }\n");
    write_file(dir / "b.glsl", "float b() { return 1.0; }\n");
    const gl::ResolvedSource r =
        gl::ShaderSources::directory(dir.string()).resolve("main.frag", {"X 2", "Y"});
    EXPECT_EQ(r.files, (std::vector<std::string>{"main.frag", "a.glsl", "b.glsl"}));
    EXPECT_EQ(count(r.text, "float b()"), 1u);
    EXPECT_EQ(r.text.rfind("#version 450 core\n#define X 2\n#define Y\n#line 2 0\n", 0), 0u)
        << r.text;
    EXPECT_NE(r.text.find("#line 1 1\n// a\n#line 1 2\nfloat b()"), std::string::npos) << r.text;
    EXPECT_NE(r.text.find("#line 4 0\nvoid main() {}"), std::string::npos) << r.text;
}

TEST(ShaderSources, ReportsMissingAndMalformedFiles) {
    const fs::path dir = scratch_dir("bad_includes");
    write_file(dir / "missing.frag", "#version 450 core\n#include \"nowhere.glsl\"\n");
    write_file(dir / "malformed.frag", "#version 450 core\n#include <x.glsl>\n");
    write_file(dir / "noversion.frag", "void main() {}\n");
    write_file(dir / "loop.glsl", "#include \"loop2.glsl\"\n");
    write_file(dir / "loop2.glsl", "#include \"loop.glsl\"\n");
    write_file(dir / "loop.frag", "#version 450 core\n#include \"loop.glsl\"\n");
    const gl::ShaderSources sources = gl::ShaderSources::directory(dir.string());
    EXPECT_THROW(sources.resolve("missing.frag", {}), Error);
    EXPECT_THROW(sources.resolve("malformed.frag", {}), Error);
    EXPECT_THROW(sources.resolve("noversion.frag", {}), Error);
    EXPECT_THROW(sources.resolve("../x.frag", {}), Error);
    EXPECT_NO_THROW(sources.resolve("loop.frag", {}));  // each file once: no endless recursion
    EXPECT_THROW(gl::ShaderSources::directory((dir / "none").string()), Error);
    // A key with a bit that the technique has no variant for, or an unknown bit.
    EXPECT_THROW(gl::shader_variant(gl::VariantKey::scene(Technique::Bump, gl::kFadeFast)), Error);
    EXPECT_THROW(gl::shader_variant(gl::VariantKey::scene(Technique::Lean, 64u)), Error);
}

// Before: an #include was confined by its spelling only: a link in the shader folder to a file
// outside it was read, and the outside file's text reached the compile log's messages. Where the
// name leads is checked before the file is read; a link that stays inside is followed.
TEST(ShaderSources, IncludeThroughALinkOutOfTheFolderIsRefused) {
    const fs::path root = scratch_dir("include_links");
    fs::create_directories(root / "shaders");
    fs::create_directories(root / "outside");
    write_file(root / "outside" / "secret.glsl", "SECRET TEXT OF AN OUTSIDE FILE\n");
    write_file(root / "shaders" / "inner.glsl", "float inner() { return 1.0; }\n");
    fs::create_symlink("../outside/secret.glsl", root / "shaders" / "out.glsl");
    fs::create_symlink("../outside", root / "shaders" / "sub");
    fs::create_symlink("inner.glsl", root / "shaders" / "in.glsl");
    write_file(root / "shaders" / "a.frag", "#version 450 core\n#include \"out.glsl\"\n");
    write_file(root / "shaders" / "b.frag", "#version 450 core\n#include \"sub/secret.glsl\"\n");
    write_file(root / "shaders" / "c.frag", "#version 450 core\n#include \"in.glsl\"\n");
    fs::create_symlink("../outside/secret.glsl", root / "shaders" / "d.frag");
    const gl::ShaderSources sources = gl::ShaderSources::directory((root / "shaders").string());
    for (const char* main_file : {"a.frag", "b.frag", "d.frag"}) {
        SCOPED_TRACE(main_file);
        try {
            (void)sources.resolve(main_file, {});
            ADD_FAILURE() << "no error";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.cause()).find("resolves outside the shader folder"),
                      std::string::npos)
                << e.what();
            EXPECT_EQ(std::string(e.what()).find("SECRET"), std::string::npos) << e.what();
        }
    }
    const gl::ResolvedSource inside = sources.resolve("c.frag", {});
    EXPECT_NE(inside.text.find("float inner()"), std::string::npos) << inside.text;
}

// The drivers' log formats, resolved to files and lines (no context needed).
TEST(ShaderSources, CompileLogsOfEachDriverNameTheFileAndLine) {
    const fs::path dir = scratch_dir("compile_logs");
    const gl::ShaderSources folder = gl::ShaderSources::directory(dir.string());
    gl::ResolvedSource source;
    source.files = {"scene.frag", "lean_shading.glsl"};
    const std::string header = (dir / "lean_shading.glsl").string();
    const std::string main_file = (dir / "scene.frag").string();

    // Mesa: the first error names the file, even after a warning; the others keep their files.
    Error mesa = gl::compile_error(GL_FRAGMENT_SHADER, "scene.frag", source, folder,
                                   "0:12(5): warning: unused x\n"
                                   "1:221(1): error: illegal use of reserved word `this'\n"
                                   "1:221(1): error: syntax error\n");
    EXPECT_EQ(mesa.file(), header);
    EXPECT_EQ(mesa.cause(),
              "line 221, column 1: error: illegal use of reserved word `this'; " + main_file +
                  " line 12, column 5: warning: unused x; line 221, column 1: error: syntax "
                  "error (included by the fragment shader scene.frag, which does not compile)");

    // NVIDIA.
    Error nvidia = gl::compile_error(GL_FRAGMENT_SHADER, "scene.frag", source, folder,
                                     "1(40) : error C1008: undefined variable \"q\"\n");
    EXPECT_EQ(nvidia.file(), header);
    EXPECT_EQ(nvidia.cause().rfind("line 40: error C1008: undefined variable \"q\"", 0), 0u)
        << nvidia.what();

    // AMD, Intel and glslang.
    Error glslang = gl::compile_error(GL_VERTEX_SHADER, "scene.frag", source, folder,
                                      "ERROR: 0:7: 'x' : undeclared identifier\n"
                                      "ERROR: 1 compilation errors.  No code generated.\n");
    EXPECT_EQ(glslang.file(), main_file);
    EXPECT_EQ(glslang.cause(),
              "line 7: error: 'x' : undeclared identifier; ERROR: 1 compilation errors.  No code "
              "generated. (the vertex shader scene.frag does not compile)");

    // A log without locations is passed on; an unknown source string is named as such.
    Error plain =
        gl::compile_error(GL_COMPUTE_SHADER, "scene.frag", source, folder, "out of registers\n");
    EXPECT_EQ(plain.file(), main_file);
    EXPECT_EQ(plain.cause(), "out of registers (the compute shader scene.frag does not compile)");
    Error unknown =
        gl::compile_error(GL_FRAGMENT_SHADER, "scene.frag", source, folder, "7:3(2): error: x\n");
    EXPECT_EQ(unknown.file(), "source string 7");
    Error empty = gl::compile_error(GL_FRAGMENT_SHADER, "scene.frag", source, folder, "");
    EXPECT_EQ(empty.cause().rfind("the driver gave no log", 0), 0u) << empty.what();

    // The embedded shaders are named by their names under shaders/.
    Error embedded = gl::compile_error(GL_FRAGMENT_SHADER, "scene.frag", source,
                                       gl::ShaderSources::embedded(), "1:3(1): error: x\n");
    EXPECT_EQ(embedded.file(), "lean_shading.glsl");
}

class GlShaders : public GlTest {};

TEST_F(GlShaders, EveryVariantCompilesAndLinks) {
    const gl::ShaderSources sources = gl::ShaderSources::embedded();
    for (const gl::ShaderVariant& variant : gl::shader_variants()) {
        gl::Program program = gl::build_program(sources, variant);
        EXPECT_TRUE(glIsProgram(program.get())) << variant.name;
    }
}

// The fragment stage's uniform block as the driver lays it out equals its C++ mirror
// (leanfade/gl/detail/shading_block.hpp): every member at the C++ offset, the block within the buffer
// the renderer allocates, and the binding points of shaders/bindings.glsl.
// One std140 block of a program: the driver's offsets equal the C++ mirror's, every member of the
// block is in the mirror, the binding point is the one of shaders/bindings.glsl and the block fits
// the buffer the renderer allocates.
void check_block(GLuint p, const std::string& variant, const char* block_name,
                 std::span<const gl::BlockMember> members, int binding, std::size_t cpp_size,
                 std::size_t buffer_size) {
    const GLuint block = glGetProgramResourceIndex(p, GL_UNIFORM_BLOCK, block_name);
    ASSERT_NE(block, GL_INVALID_INDEX) << variant << " " << block_name;
    const GLenum block_props[] = {GL_BUFFER_DATA_SIZE, GL_BUFFER_BINDING, GL_NUM_ACTIVE_VARIABLES};
    GLint block_values[3] = {0, -1, -1};
    glGetProgramResourceiv(p, GL_UNIFORM_BLOCK, block, 3, block_props, 3, nullptr, block_values);
    EXPECT_LE(std::size_t(block_values[0]), buffer_size) << variant << " " << block_name;
    EXPECT_GE(std::size_t(block_values[0]), cpp_size) << variant << " " << block_name;
    EXPECT_EQ(block_values[1], binding) << variant << " " << block_name;
    EXPECT_EQ(block_values[2], GLint(members.size())) << variant << " " << block_name;
    for (const gl::BlockMember& member : members) {
        const GLuint index = glGetProgramResourceIndex(p, GL_UNIFORM, member.name.c_str());
        // std140 blocks keep every member active (the layout is fixed), so all must be found.
        ASSERT_NE(index, GL_INVALID_INDEX) << variant << ": " << member.name;
        const GLenum props[] = {GL_OFFSET, GL_BLOCK_INDEX};
        GLint values[2] = {-1, -1};
        glGetProgramResourceiv(p, GL_UNIFORM, index, 2, props, 2, nullptr, values);
        EXPECT_EQ(values[0], GLint(member.offset)) << variant << ": " << member.name;
        EXPECT_EQ(values[1], GLint(block)) << variant << ": " << member.name;
    }
}

// The uniform blocks as the driver lays them out equal their C++ mirrors
// (leanfade/gl/detail/shading_block.hpp), and the LEAN map's sampler is on its named unit.
TEST_F(GlShaders, UniformBlocksMatchTheirCppMirrors) {
    const gl::ShaderSources sources = gl::ShaderSources::embedded();
    int checked_programs = 0;
    for (const gl::ShaderVariant& variant : gl::shader_variants()) {
        if (variant.vertex != "scene.vert") continue;
        gl::Program program = gl::build_program(sources, variant);
        const GLuint p = program.get();
        check_block(p, variant.name, "LfObjectBlock", gl::object_block_members(),
                    gl::bindings::LF_BINDING_OBJECT_BLOCK, sizeof(gl::LfObjectUniforms),
                    sizeof(gl::LfObjectUniforms));
        if (variant.fragment != "scene.frag") continue;  // the constant colour reads no more
        check_block(p, variant.name, "LfShadingBlock", gl::shading_block_members(),
                    gl::bindings::LF_BINDING_SHADING_BLOCK, sizeof(gl::LfShadingUniforms),
                    gl::kShadingBlockStd140Size);
        const auto expect_unit = [&](const char* name, int binding) {
            const GLint sampler = glGetUniformLocation(p, name);
            ASSERT_GE(sampler, 0) << variant.name << " " << name;
            GLint unit = -1;
            glGetUniformiv(p, sampler, &unit);
            EXPECT_EQ(unit, binding) << variant.name << " " << name;
        };
        const bool layered = std::find(variant.defines.begin(), variant.defines.end(),
                                       "LF_LAYERED") != variant.defines.end();
        if (layered) {
            // Bump layers: their block, and each sampler on its named unit (docs/math.md §6).
            check_block(p, variant.name, "LfLayerBlock", gl::layer_block_members(),
                        gl::bindings::LF_BINDING_LAYER_BLOCK, sizeof(gl::LfLayerUniforms),
                        sizeof(gl::LfLayerUniforms));
            for (int i = 0; i < 4; ++i)
                expect_unit(("u_layer_maps[" + std::to_string(i) + "]").c_str(),
                            gl::bindings::LF_BINDING_LAYER_MAPS + i);
            // The cross terms enter M only, which the lobes without second moments drop.
            if (std::find(variant.defines.begin(), variant.defines.end(), "LF_READS_MOMENTS") !=
                variant.defines.end())
                expect_unit("u_cross_terms", gl::bindings::LF_BINDING_CROSS_TERMS);
            expect_unit("u_layer_weights", gl::bindings::LF_BINDING_LAYER_WEIGHTS);
        } else {
            expect_unit("u_lean", gl::bindings::LF_BINDING_LEAN_MAP);
        }
        ++checked_programs;
    }
    EXPECT_GE(checked_programs, int(all_techniques().size()));
}

// A copy of shaders/ in `dir`.
void copy_shaders(const fs::path& dir) {
    const fs::path source_dir = fs::path(LEANFADE_SOURCE_DIR) / "shaders";
    for (const auto& entry : fs::directory_iterator(source_dir))
        fs::copy_file(entry.path(), dir / entry.path().filename());
}

// Appends `bad` to `file` on a line of its own; returns that line's number.
int append_line(const fs::path& file, const std::string& bad) {
    std::string text;
    {
        std::ifstream in(file, std::ios::binary);
        std::ostringstream s;
        s << in.rdbuf();
        text = s.str();
    }
    if (!text.empty() && text.back() != '\n') text += '\n';
    text += "\n" + bad + "\n";
    write_file(file, text);
    return int(count(text, "\n"));  // text ends with a newline: the last line, counted from 1
}

TEST_F(GlShaders, CompileErrorsNameTheIncludedFileAndLine) {
    const fs::path dir = scratch_dir("broken_shaders");
    copy_shaders(dir);
    const int line = append_line(dir / "lean_shading.glsl", "this is not GLSL;");
    try {
        gl::build_program(gl::ShaderSources::directory(dir.string()),
                          gl::shader_variant(gl::VariantKey::scene(Technique::Lean)));
        FAIL() << "a broken shared header must not compile";
    } catch (const Error& e) {
        // The error is in the included file: its path, its line, and the stage that includes it.
        EXPECT_EQ(e.file(), (dir / "lean_shading.glsl").string()) << e.what();
        EXPECT_EQ(e.cause().rfind("line " + std::to_string(line) + ", column 1: error:", 0), 0u)
            << e.what();
        EXPECT_NE(e.cause().find("fragment shader scene.frag"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
    // The driver's info log is not an error of the GL API.
    EXPECT_TRUE(context().take_errors().empty());
}

TEST_F(GlShaders, CompileErrorsNameTheMainFileAndLine) {
    const fs::path dir = scratch_dir("broken_main_shader");
    copy_shaders(dir);
    const int line = append_line(dir / "scene.vert", "float broken = ;");
    for (const gl::VariantKey variant : {gl::VariantKey::scene(Technique::Bump),
                                         gl::VariantKey::scene(Technique::Lean, gl::kPlainColor)}) {
        try {
            gl::build_program(gl::ShaderSources::directory(dir.string()),
                              gl::shader_variant(variant));
            FAIL() << gl::variant_name(variant) << ": a broken vertex stage must not compile";
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), (dir / "scene.vert").string()) << e.what();
            // The variant's #defines after #version do not shift the line numbers.
            EXPECT_EQ(e.cause().rfind("line " + std::to_string(line) + ",", 0), 0u) << e.what();
            EXPECT_NE(e.cause().find("(the vertex shader scene.vert does not compile)"),
                      std::string::npos)
                << e.what();
        }
    }
    EXPECT_TRUE(context().take_errors().empty());
}

TEST_F(GlShaders, ComputeCompileErrorsNameTheFileAndLine) {
    const fs::path dir = scratch_dir("broken_compute_shader");
    copy_shaders(dir);
    const int line = append_line(dir / "generate_lean.comp", "float broken = ;");
    try {
        gl::build_compute_program(gl::ShaderSources::directory(dir.string()), "generate_lean.comp",
                                  {"SOURCE_HEIGHT", "SLICE_FORMAT rgba16f"});
        FAIL() << "a broken compute shader must not compile";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), (dir / "generate_lean.comp").string()) << e.what();
        EXPECT_EQ(e.cause().rfind("line " + std::to_string(line) + ",", 0), 0u) << e.what();
        EXPECT_NE(e.cause().find("compute shader generate_lean.comp"), std::string::npos)
            << e.what();
    }
    EXPECT_TRUE(context().take_errors().empty());
}

}  // namespace
}  // namespace leanfade::test
