// The OpenGL part of the installed package (find_package(leanfade COMPONENTS gl)): every
// technique of the table has its shader variants, and the installed shaders resolve into one
// self-contained source per variant. No GL context is needed for either.
//
// Usage: consumer_gl SHADER_FOLDER   (the package's leanfade_SHADER_DIR). Exit 0 when every check
// holds, 1 with a message naming the first that does not.
#include <cstdio>
#include <string>

#include <leanfade/gl/shader_library.hpp>
#include <leanfade/leanfade.hpp>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: consumer_gl SHADER_FOLDER\n");
        return 2;
    }
    try {
        const auto sources = leanfade::gl::ShaderSources::directory(argv[1]);
        int resolved = 0;
        for (const leanfade::TechniqueInfo& row : leanfade::kTechniques) {
            const leanfade::gl::ShaderVariant& variant =
                leanfade::gl::shader_variant(leanfade::gl::VariantKey::scene(row.id));
            const leanfade::gl::ResolvedSource source =
                sources.resolve(variant.fragment, variant.defines);
            if (source.text.find("#include") != std::string::npos ||
                source.text.find("LfMoments lf_unpack(") == std::string::npos ||
                source.text.find("#define LF_TECHNIQUE " + std::to_string(row.shader_technique)) ==
                    std::string::npos) {
                std::fprintf(stderr, "consumer_gl: FAILED: %s is not resolved with its defines\n",
                             variant.name.c_str());
                return 1;
            }
            ++resolved;
        }
        std::printf("consumer_gl: %d techniques, %zu shader variants, %d resolved from %s: ok\n",
                    int(leanfade::kTechniques.size()), leanfade::gl::shader_variants().size(),
                    resolved, argv[1]);
    } catch (const leanfade::Error& e) {
        std::fprintf(stderr, "consumer_gl: %s\n", e.what());
        return 1;
    }
    return 0;
}
