// Shader sources: #include resolution, variants, disk folders, glslangValidator and the driver.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "gl_test_helpers.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/gl/shader_library.hpp"

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

TEST(ShaderSources, FragmentStageIncludesTheSharedHeaderOnce) {
    const gl::ShaderSources sources = gl::ShaderSources::embedded();
    const gl::ResolvedSource r = sources.resolve("scene.frag", {"TECHNIQUE_LEAN"});
    ASSERT_EQ(r.files.size(), 2u);
    EXPECT_EQ(r.files[0], "scene.frag");
    EXPECT_EQ(r.files[1], "lean_shading.glsl");
    EXPECT_EQ(r.text.rfind("#version 450 core\n#define TECHNIQUE_LEAN\n", 0), 0u) << r.text;
    EXPECT_EQ(count(r.text, "LF_FN LfShade lf_shade_lean("), 1u);
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
    EXPECT_THROW(gl::shader_variant("scene_unknown"), Error);
}

class GlShaders : public GlTest {};

TEST_F(GlShaders, EveryVariantCompilesAndLinks) {
    const gl::ShaderSources sources = gl::ShaderSources::embedded();
    for (const gl::ShaderVariant& variant : gl::shader_variants()) {
        gl::Program program = gl::build_program(sources, variant);
        EXPECT_TRUE(glIsProgram(program.get())) << variant.name;
    }
}

TEST_F(GlShaders, CompileErrorsNameTheFiles) {
    const fs::path dir = scratch_dir("broken_shaders");
    const fs::path source_dir = fs::path(LEANFADE_SOURCE_DIR) / "shaders";
    for (const auto& entry : fs::directory_iterator(source_dir))
        fs::copy_file(entry.path(), dir / entry.path().filename());
    {
        std::ofstream out(dir / "lean_shading.glsl", std::ios::app);
        out << "\nthis is not GLSL;\n";
    }
    try {
        gl::build_program(gl::ShaderSources::directory(dir.string()),
                          gl::shader_variant("scene_lean"));
        FAIL() << "a broken shared header must not compile";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "scene.frag");
        EXPECT_NE(e.cause().find("1 = lean_shading.glsl"), std::string::npos) << e.what();
    }
    // The driver's info log is not an error of the GL API.
    EXPECT_TRUE(context().take_errors().empty());
}

}  // namespace
}  // namespace leanfade::test
