// Presets (core/preset.hpp): exact JSON round trip, defaults for missing keys, and strict errors
// that name the file and the key.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/preset.hpp"

namespace leanfade {
namespace {

Preset unusual_preset() {
    Preset p;
    p.scene = "torus";
    p.bumps.source = "ridges";
    p.bumps.from = BakeSource::Normal;
    p.bumps.directx = true;
    p.bumps.bits = StoragePolicy::fixed(Storage::Float16);
    p.bumps.seed = 4000000000u;
    p.bumps.texture_size = 128;
    ShadingSettings& s = p.shading;
    s.light_direction = {0.1f, -0.7f, 0.3f};
    s.light_color = {1.5f, 1.25f, 0.9f};
    s.ambient = {0.01f, 0.02f, 0.03f};
    s.kd = {0.3f, 0.31f, 0.32f};
    s.ks = {0.7f, 0.8f, 0.9f};
    s.shininess = 1234.5f;
    s.fresnel_bias = 0.05f;
    s.fresnel_scale = 0.95f;
    s.fade = 0.3333333f;
    s.pmax = 7.5f;
    s.fade_exponent = 1.5f;
    s.fade_distance = FadeDistance::Eye;
    s.fog = FogMode::Exp2;
    s.fog_color = {0.2f, 0.3f, 0.4f};
    s.fog_start = 1.5f;
    s.fog_end = 80.0f;
    s.fog_density = 0.0123f;
    s.bump_strength = 2.5f;
    s.tiling = 3.0f;
    s.mip_bias = -0.75f;
    s.anisotropy = 8;
    s.msaa = 4;
    p.camera.target = {0.25f, -0.1f, 0.0f};
    p.camera.direction = {0.6f, 0.48f, 0.64f};
    p.camera.distance = 17.25f;
    p.camera.fov_y_degrees = 41.0f;
    p.techniques = {Technique::Bump, Technique::Fade, Technique::Reference};
    p.layout = PaneLayout::SideBySide;
    p.divider = 0.3f;
    p.reference_samples = 6;
    p.resolution_scale = 0.5f;
    p.fly_away = {1.5f, 120.0f, 12.0f};
    return p;
}

TEST(Preset, RoundTripIsExact) {
    const Preset p = unusual_preset();
    const std::string text = preset_to_json(p);
    const Preset back = preset_from_json(text, "round.json");
    EXPECT_EQ(preset_to_json(back), text);
    EXPECT_EQ(back.scene, "torus");
    EXPECT_EQ(back.bumps.seed, 4000000000u);
    EXPECT_TRUE(back.bumps.directx);
    EXPECT_EQ(back.shading.fade, p.shading.fade);  // bit-exact floats
    EXPECT_EQ(back.shading.fog_density, p.shading.fog_density);
    EXPECT_EQ(back.shading.light_direction, p.shading.light_direction);
    EXPECT_EQ(back.shading.fade_distance, FadeDistance::Eye);
    EXPECT_EQ(back.shading.fog, FogMode::Exp2);
    EXPECT_EQ(back.shading.msaa, 4);
    EXPECT_EQ(back.camera.target, p.camera.target);
    EXPECT_EQ(back.camera.distance, 17.25f);
    EXPECT_EQ(back.techniques, p.techniques);
    EXPECT_EQ(back.layout, PaneLayout::SideBySide);
    EXPECT_EQ(back.fly_away.far_distance, 120.0f);
    // Shortest exact numbers: 0.05f is written as 0.05, not 0.05000000074505806.
    EXPECT_NE(text.find("\"fresnel_bias\": 0.05,"), std::string::npos) << text;
}

TEST(Preset, DefaultsRoundTrip) {
    const Preset defaults;
    EXPECT_EQ(preset_to_json(preset_from_json(preset_to_json(defaults), "d.json")),
              preset_to_json(defaults));
    EXPECT_EQ(preset_to_json(preset_from_json("{}", "empty.json")), preset_to_json(defaults));
}

TEST(Preset, MissingKeysKeepTheirDefaults) {
    const Preset p = preset_from_json(R"({"shading": {"fade": 0.5}, "camera": {"distance": 9}})",
                                      "partial.json");
    EXPECT_EQ(p.shading.fade, 0.5f);
    EXPECT_EQ(p.camera.distance, 9.0f);
    const Preset defaults;
    EXPECT_EQ(p.shading.shininess, defaults.shading.shininess);
    EXPECT_EQ(p.scene, defaults.scene);
    EXPECT_EQ(p.techniques, defaults.techniques);
}

TEST(Preset, ReadsFiles) {
    const auto dir = std::filesystem::path(LEANFADE_TEST_TMP) / "preset_files";
    std::filesystem::create_directories(dir);
    const auto path = (dir / "p.json").string();
    {
        std::ofstream out(path);
        out << preset_to_json(unusual_preset());
    }
    EXPECT_EQ(preset_to_json(read_preset(path)), preset_to_json(unusual_preset()));
    const auto missing = (dir / "missing.json").string();
    try {
        read_preset(missing);
        FAIL() << "a missing file must throw";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), missing);
    }
}

struct BadCase {
    const char* text;
    const char* key;    // named in the message as key '<key>'
    const char* cause;  // a part of the cause
};

TEST(Preset, BadValuesNameTheFileAndTheKey) {
    const BadCase cases[] = {
        {R"({"scene": "teapot", "bogus": 1})", "bogus", "unknown key"},
        {R"({"shading": {"shinyness": 3}})", "shading.shinyness", "unknown key"},
        {R"({"view": {"fly_away": {"speed": 3}}})", "view.fly_away.speed", "unknown key"},
        {R"({"shading": {"fade": "0.5"}})", "shading.fade", "expected a number"},
        {R"({"shading": {"kd": [1, 2]}})", "shading.kd", "array of 3"},
        {R"({"shading": {"kd": [1, "x", 2]}})", "shading.kd[1]", "expected a number"},
        {R"({"shading": {"msaa": 2.5}})", "shading.msaa", "integer"},
        {R"({"shading": {"anisotropy": 99}})", "shading.anisotropy", "[1, 16]"},
        {R"({"bumps": {"directx": 1}})", "bumps.directx", "true or false"},
        {R"({"bumps": {"seed": -1}})", "bumps.seed", "must be in"},
        {R"({"bumps": {"bits": "12"}})", "bumps.bits", "expected"},
        {R"({"shading": {"fade": NaN}})", "shading.fade", "not valid JSON"},
        {R"({"shading": {"fade": 1e999}})", "shading.fade", "not valid JSON"},
        {R"({"shading": {"fade": 1e39}})", "shading.fade", "finite"},
        {R"({"shading": {"shininess": -1}})", "shading.shininess", "must be > 0"},
        {R"({"shading": {"pmax": 0.5}})", "shading.pmax", ">= 1"},
        {R"({"shading": {"light_direction": [0, 0, 0]}})", "shading.light_direction", "zero"},
        {R"({"shading": {"fog": "fast"}})", "shading.fog", "unknown fog mode"},
        {R"({"shading": {"fade_distance": 3}})", "shading.fade_distance", "expected a string"},
        {R"({"shading": {"fog": "linear", "fog_start": 10, "fog_end": 5}})", "shading.fog_end",
         "greater"},
        {R"({"camera": {"distance": 0.5}})", "camera.distance", "(1, "},
        {R"({"camera": {"direction": [0, 0, 0]}})", "camera.direction", "non-zero"},
        {R"({"camera": {"fov_y_degrees": 180}})", "camera.fov_y_degrees", "(1, 170)"},
        {R"({"view": {"layout": "grid"}})", "view.layout", "expected"},
        {R"({"view": {"layout": "split", "techniques": ["lean"]}})", "view.techniques",
         "exactly 2"},
        {R"({"view": {"layout": "split", "techniques": ["lean", "lean"]}})", "view.techniques",
         "twice"},
        {R"({"view": {"techniques": "lean"}})", "view.techniques", "array"},
        {R"({"view": {"divider": 2}})", "view.divider", "[0, 1]"},
        {R"({"view": {"resolution_scale": 0}})", "view.resolution_scale", "[0.1, 1]"},
        {R"({"view": {"fly_away": {"near": 5, "far": 4}}})", "view.fly_away.far", "greater"},
        {R"({"scene": "a", "scene": "b"})", "scene", "more than once"},
        {R"({"shading": {"fade": 1, "fade": 2}})", "shading.fade", "more than once"},
        {R"({"leanfade_preset": 2})", "leanfade_preset", "version 2"},
        {R"([1, 2])", "(top level)", "expected an object"},
        {R"({"scene": ""})", "scene", "empty"},
    };
    for (const BadCase& c : cases) {
        SCOPED_TRACE(c.text);
        try {
            preset_from_json(c.text, "bad.json");
            ADD_FAILURE() << "accepted";
        } catch (const Error& e) {
            const std::string message = e.what();
            EXPECT_EQ(e.file(), "bad.json");
            EXPECT_NE(message.find(std::string("key '") + c.key + "'"), std::string::npos)
                << message;
            EXPECT_NE(message.find(c.cause), std::string::npos) << message;
        }
    }
}

TEST(Preset, BrokenJsonNamesTheFile) {
    try {
        preset_from_json("{\"scene\": ", "broken.json");
        FAIL() << "accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "broken.json");
        EXPECT_NE(std::string(e.what()).find("not valid JSON"), std::string::npos) << e.what();
    }
}

// Expects read_preset(path) to throw an Error for `path` whose cause is exactly `cause`.
void expect_read_error(const std::string& path, const std::string& cause) {
    try {
        read_preset(path);
        ADD_FAILURE() << path << ": accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), path);
        EXPECT_EQ(e.cause(), cause);
    }
}

// Found by an outside probe: `--preset` on a FIFO blocked forever, on /dev/zero it grew until
// bad_alloc, and a directory was "not valid JSON". Presets are now read by the one reader of
// regular text files with a size limit.
TEST(PresetFiles, DirectoryFifoDeviceAndHugeFilesAreRefusedWithoutReading) {
    const auto dir = std::filesystem::path(LEANFADE_TEST_TMP) / "preset_hostile";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "folder.json");
    expect_read_error((dir / "folder.json").string(), "is a directory, not a preset file");
    expect_read_error("/dev/zero", "is not a regular file");

    const std::string fifo = (dir / "pipe.json").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
    const int holder = ::open(fifo.c_str(), O_RDWR | O_NONBLOCK);  // the test cannot block
    ASSERT_GE(holder, 0);
    expect_read_error(fifo, "is not a regular file");
    ::close(holder);

    const std::string huge = (dir / "huge.json").string();
    std::ofstream(huge) << "{\"scene\": \"teapot\"" << std::string(std::size_t(1) << 20, ' ')
                        << "}";
    expect_read_error(huge, "file of 1048595 bytes exceeds the limit of 1048576 bytes for a "
                            "preset file");
    expect_read_error((dir / "missing.json").string(), "file not found");
}

// Found by an outside probe: text of the preset reached messages raw (newlines, terminal escape
// sequences). It is escaped, and names with control characters are refused.
TEST(PresetFiles, FileTextInMessagesIsEscaped) {
    const std::pair<std::string, std::string> cases[] = {
        {"{\"sh\\u001b[31mading\": 1}", "key 'sh\\x1B[31mading': unknown key"},
        {"{\"scene\": \"a\\nb.obj\"}", "key 'scene': contains control characters ('a\\x0Ab.obj')"},
        {"{\"view\": {\"techniques\": [\"le\\u001b]0;x\\u0007an\"]}}",
         "key 'view.techniques': contains control characters ('le\\x1B]0;x\\x07an')"},
        {"{\"scene\": \x1b[2J}", "not valid JSON: "},
    };
    for (const auto& [text, expected] : cases) {
        SCOPED_TRACE(text);
        try {
            preset_from_json(text, "p.json");
            ADD_FAILURE() << "accepted";
        } catch (const Error& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find(expected), std::string::npos) << message;
            for (const char c : message)
                EXPECT_TRUE(static_cast<unsigned char>(c) >= 0x20 && c != 0x7F) << message;
        }
    }
}

TEST(InputText, EscapesControlCharactersInvalidUtf8AndLongText) {
    EXPECT_EQ(escape_text("plain text, 1.5"), "plain text, 1.5");
    EXPECT_EQ(escape_text("a\nb\x1b[31mc\\"), "a\\x0Ab\\x1B[31mc\\x5C");
    EXPECT_EQ(escape_text("caf\xC3\xA9 \xE2\x9C\x93"), "caf\xC3\xA9 \xE2\x9C\x93");  // UTF-8 kept
    EXPECT_EQ(escape_text("\xC3(\xFF\xC2\x9B"), "\\xC3(\\xFF\\xC2\\x9B");  // invalid, C1 CSI
    // A right-to-left override.
    EXPECT_EQ(escape_text("\xE2\x80\xAE" "evil"), "\\xE2\\x80\\xAEevil");
    EXPECT_EQ(escape_text(std::string(300, 'x'), 10), std::string(10, 'x') + "...");
    EXPECT_EQ(escape_text(std::string("a\0b", 3)), "a\\x00b");
}

}  // namespace
}  // namespace leanfade
