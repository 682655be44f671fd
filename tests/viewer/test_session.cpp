// The viewer's state without a window, through a headless EGL context: loading is all or
// nothing, a shader error keeps the last good programs, presets round-trip; and the two GL
// additions the viewer needs (Renderer::render_to, Context::adopt_current).
#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/scene/detail/scene.hpp"
#include "leanfade/viewer/session.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::viewer {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
    return leanfade::test::fresh_scratch_folder("viewer", name);
}

// As `leanfade render` loads bumps: built-in sets are baked, anything else is an image file.
PackedLeanMap load_bumps(const BumpSource& source, const ShadingSettings& settings) {
    BakeOptions options;
    options.strength = settings.bump_strength;
    const auto& names = builtin_bump_names();
    const bool builtin = std::find(names.begin(), names.end(), source.source) != names.end();
    const Image height = builtin ? make_builtin_height(source.source, 32, source.seed)
                                 : io::read_image(source.source);
    return pack_lean_map(bake_lean_map(height, BakeSource::Height, options, source.source).map,
                         Storage::Unorm16, "test");
}

Preset small_preset() {
    Preset p;
    p.scene = "sphere";
    p.bumps.source = "bumps";
    p.bumps.texture_size = 32;
    return p;
}

class SessionTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        gl::ContextOptions options;
        options.record_errors = true;
        context_ = std::make_unique<gl::Context>(options);
    }
    static void TearDownTestSuite() { context_.reset(); }
    void TearDown() override {
        std::string all;
        for (const std::string& e : context_->take_errors()) all += e + "\n";
        EXPECT_TRUE(all.empty()) << "GL errors:\n" << all;
    }

    std::unique_ptr<Session> make_session(gl::ShaderSources sources = gl::ShaderSources::embedded(),
                                          Preset preset = small_preset()) {
        const scene::Mesh mesh = scene::make_scene_mesh(preset.scene);
        const PackedLeanMap map = load_bumps(preset.bumps, preset.shading);
        return std::make_unique<Session>(*context_, std::move(sources), load_bumps,
                                         std::move(preset), mesh, map);
    }

    static Image render(Session& session, gl::Technique technique = gl::Technique::Lean) {
        gl::RenderRequest request;
        request.technique = technique;
        request.width = 40;
        request.height = 32;
        request.view = session.camera().view();
        request.settings = session.preset().shading;
        return session.renderer().render(request);
    }

    static std::unique_ptr<gl::Context> context_;
};

std::unique_ptr<gl::Context> SessionTest::context_;

bool contains(const std::vector<std::string>& messages, const std::string& part) {
    for (const std::string& m : messages)
        if (m.find(part) != std::string::npos) return true;
    return false;
}

TEST_F(SessionTest, AcceptsEveryTechniqueOfTheTable) {
    auto session = make_session();
    EXPECT_EQ(session->techniques(), std::vector<gl::Technique>{gl::Technique::Lean});
    for (gl::Technique t : gl::all_techniques()) {
        session->preset().techniques = {t};
        EXPECT_EQ(session->techniques(), std::vector<gl::Technique>{t}) << gl::to_string(t);
    }
}

TEST_F(SessionTest, AMissingSceneKeepsTheMesh) {
    auto session = make_session();
    const Image before = render(*session);
    const std::string description = session->mesh_description();
    const std::uint64_t generation = session->generation();
    EXPECT_FALSE(session->load_scene("no/such/mesh.obj"));
    EXPECT_TRUE(contains(session->errors(), "no/such/mesh.obj"));
    EXPECT_EQ(session->mesh_description(), description);
    EXPECT_EQ(session->preset().scene, "sphere");
    EXPECT_EQ(session->generation(), generation);
    EXPECT_EQ(render(*session).pixels, before.pixels);

    EXPECT_TRUE(session->load_scene("torus"));
    EXPECT_EQ(session->preset().scene, "torus");
    EXPECT_NE(session->mesh_description().find("torus"), std::string::npos);
    EXPECT_GT(session->generation(), generation);
    EXPECT_NE(render(*session).pixels, before.pixels);
}

TEST_F(SessionTest, MissingBumpsKeepTheMap) {
    auto session = make_session();
    const Image before = render(*session);
    BumpSource missing = session->preset().bumps;
    missing.source = "no/such/bumps.png";
    EXPECT_FALSE(session->load_bumps(missing));
    EXPECT_TRUE(contains(session->errors(), "no/such/bumps.png"));
    EXPECT_EQ(session->preset().bumps.source, "bumps");
    EXPECT_EQ(render(*session).pixels, before.pixels);
    BumpSource invalid = session->preset().bumps;
    invalid.texture_size = 2;  // below kMinTextureSize
    EXPECT_FALSE(session->load_bumps(invalid));
    EXPECT_EQ(session->preset().bumps.texture_size, 32);

    BumpSource ridges = session->preset().bumps;
    ridges.source = "ridges";
    EXPECT_TRUE(session->load_bumps(ridges));
    EXPECT_EQ(session->preset().bumps.source, "ridges");
    EXPECT_NE(render(*session).pixels, before.pixels);
    // A new strength re-bakes the height map.
    const Image ridged = render(*session);
    session->preset().shading.bump_strength = 3.0f;
    EXPECT_TRUE(session->rebake_bumps());
    EXPECT_NE(render(*session).pixels, ridged.pixels);
}

TEST_F(SessionTest, AShaderErrorKeepsTheLastGoodPrograms) {
    const fs::path dir = scratch("shaders");
    for (const auto& entry : fs::directory_iterator(fs::path(LEANFADE_SOURCE_DIR) / "shaders"))
        fs::copy_file(entry.path(), dir / entry.path().filename());
    auto session = make_session(gl::ShaderSources::directory(dir.string()));
    EXPECT_TRUE(session->shaders_reloadable());
    const Image before = render(*session);
    EXPECT_TRUE(session->reload_shaders());

    const fs::path frag = dir / "scene.frag";
    const std::string good = [&] {
        std::ifstream in(frag);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }();
    std::ofstream(frag, std::ios::app) << "\nthis is not GLSL;\n";
    const std::uint64_t generation = session->generation();
    EXPECT_FALSE(session->reload_shaders());
    EXPECT_TRUE(contains(session->errors(), "scene.frag"));
    EXPECT_TRUE(contains(session->errors(), "previous shaders stay"));
    EXPECT_EQ(session->generation(), generation);
    EXPECT_EQ(render(*session).pixels, before.pixels);  // the last good program draws
    context_->take_errors();                            // the driver may report the failed compile

    std::ofstream(frag, std::ios::trunc) << good;
    EXPECT_TRUE(session->reload_shaders());
    EXPECT_EQ(render(*session).pixels, before.pixels);
}

TEST_F(SessionTest, BuiltInShadersCannotBeReloaded) {
    auto session = make_session();
    EXPECT_FALSE(session->shaders_reloadable());
    EXPECT_FALSE(session->reload_shaders());
    EXPECT_TRUE(contains(session->errors(), "built-in shaders"));
    EXPECT_EQ(session->shader_origin(), "embedded");
}

TEST_F(SessionTest, PresetsRoundTripAndBadOnesChangeNothing) {
    const fs::path dir = scratch("presets");
    auto session = make_session();
    session->preset().shading.fade = 0.75f;
    session->preset().shading.fog = FogMode::Linear;
    session->preset().techniques = {Technique::Bump, Technique::Fade};
    session->preset().layout = PaneLayout::Split;
    session->camera().orbit(30.0f, 10.0f);
    session->camera().zoom(2.0f);
    const std::string saved = preset_to_json(session->snapshot());
    const std::string path = (dir / "view.json").string();
    ASSERT_TRUE(session->save_preset(path)) << session->errors().back();

    auto other = make_session();
    ASSERT_TRUE(other->load_preset(path)) << other->errors().back();
    EXPECT_EQ(preset_to_json(other->snapshot()), saved);
    EXPECT_EQ(other->techniques(),
              (std::vector<gl::Technique>{gl::Technique::Bump, gl::Technique::Fade}));

    // Bad presets: a key, a technique, a missing scene file. Nothing changes.
    const struct {
        const char* name;
        const char* text;
        const char* message;
    } bad[] = {
        {"key.json", R"({"shading": {"fade": -1}})", "shading.fade"},
        {"technique.json", R"({"view": {"techniques": ["phong"]}})", "phong"},
        {"scene.json", R"({"scene": "no/such/mesh.obj"})", "no/such/mesh.obj"},
        {"bumps.json", R"({"bumps": {"source": "no/such/bumps.png"}})", "no/such/bumps.png"},
    };
    for (const auto& b : bad) {
        SCOPED_TRACE(b.name);
        const std::string file = (dir / b.name).string();
        std::ofstream(file) << b.text;
        const Image before = render(*other);
        EXPECT_FALSE(other->load_preset(file));
        EXPECT_TRUE(contains(other->errors(), b.message));
        EXPECT_EQ(preset_to_json(other->snapshot()), saved);
        EXPECT_EQ(render(*other).pixels, before.pixels);
    }
    EXPECT_FALSE(other->load_preset((dir / "missing.json").string()));
    EXPECT_FALSE(other->save_preset((dir / "no" / "folder" / "x.json").string()));
    EXPECT_EQ(preset_to_json(other->snapshot()), saved);
}

TEST_F(SessionTest, RenderToMatchesRender) {
    auto session = make_session();
    for (gl::Technique t : {gl::Technique::Bump, gl::Technique::Fade, gl::Technique::Reference}) {
        SCOPED_TRACE(gl::to_string(t));
        const Image expected = render(*session, t);
        gl::Texture color = gl::create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(color.get(), 1, GL_RGBA32F, 50, 40);
        gl::Framebuffer fbo = gl::create_framebuffer();
        glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
        gl::RenderRequest request;
        request.technique = t;
        request.width = 40;
        request.height = 32;
        request.view = session->camera().view();
        request.settings = session->preset().shading;
        session->renderer().render_to(request, fbo.get(), 7, 5);
        std::vector<float> rgba(50 * 40 * 4);
        glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, GLsizei(rgba.size() * sizeof(float)),
                          rgba.data());
        int mismatches = 0;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 40; ++x)
                for (int c = 0; c < 3; ++c) {
                    // GL rows are bottom first; the image's are top first.
                    const float got = rgba[std::size_t(((5 + 31 - y) * 50 + 7 + x) * 4 + c)];
                    mismatches += got != expected.at(x, y, c);
                }
        EXPECT_EQ(mismatches, 0);
    }
}

TEST_F(SessionTest, AdoptedContextsLeaveTheirOwnerAlone) {
    // No debug callback of its own: the owner's (record_errors) stays installed.
    gl::ContextOptions options;
    options.debug = false;
    {
        const auto adopted = gl::Context::adopt_current(options, "test window");
        EXPECT_EQ(adopted->platform(), "test window");
        EXPECT_EQ(adopted->renderer(), context_->renderer());
        EXPECT_NE(adopted->description().find("(test window)"), std::string::npos);
        adopted->make_current();
        glBindTexture(GL_TEXTURE_2D, 12345678);  // not a texture name: an error
        EXPECT_THROW(adopted->check("binding"), Error);
        context_->take_errors();  // the owner recorded it too
        // A renderer works in the adopted context.
        gl::Renderer renderer(*adopted);
        renderer.set_mesh(scene::make_scene_mesh("sphere"));
        renderer.set_lean_map(load_bumps(small_preset().bumps, ShadingSettings{}));
        gl::RenderRequest request;
        request.width = request.height = 16;
        EXPECT_GT(renderer.render(request).pixels.size(), 0u);
    }
    // The owner's context is still current and working.
    auto session = make_session();
    EXPECT_GT(render(*session).pixels.size(), 0u);
    context_->make_current();
}

}  // namespace
}  // namespace leanfade::viewer
