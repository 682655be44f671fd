// Typed bump sources and layers (leanfade/core/detail/bump_source.hpp): the storage choice with auto as
// a value, the one texture-size rule, the layers' checks naming their settings, and presets that
// keep layers and surface maps.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "leanfade/core/detail/bump_source.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/preset.hpp"

namespace leanfade {
namespace {

// The setting an Error names and whether its cause holds `part`.
void expect_error(const std::function<void()>& f, const std::string& setting,
                  const std::string& part) {
    try {
        f();
        ADD_FAILURE() << "accepted; expected " << setting << ": " << part;
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), setting) << e.what();
        EXPECT_NE(e.cause().find(part), std::string::npos) << e.what();
    }
}

TEST(StoragePolicy, AutoIsAValueAndTheDefaultEverywhere) {
    EXPECT_TRUE(BumpSource{}.bits.automatic);
    EXPECT_EQ(BumpSource{}.bits.storage, Storage::Unorm16);  // the first bake of auto
    EXPECT_EQ(Preset{}.bumps.bits, BumpSource{}.bits);
    EXPECT_STREQ(to_string(StoragePolicy::measured()), "auto");
    EXPECT_EQ(BumpSource{}.bits, StoragePolicy::measured());
    EXPECT_NE(preset_to_json(Preset{}).find("\"bits\": \"auto\""), std::string::npos);
    for (const std::string& name : bake_storage_names()) {
        const StoragePolicy bits = parse_storage_policy(name);
        EXPECT_EQ(to_string(bits), name);
        EXPECT_EQ(bits.automatic, name == "auto") << name;
    }
    EXPECT_EQ(parse_storage_policy("16f"), StoragePolicy::fixed(Storage::Float16));
    EXPECT_NE(parse_storage_policy("16"), StoragePolicy::measured());  // 16 is not auto
    expect_error([] { parse_storage_policy("12"); }, "bits", "got");
    expect_error([] { parse_storage_policy("12", "--bits"); }, "--bits", "got");
}

TEST(TextureSize, OneRuleWithTheImageLimit) {
    EXPECT_NO_THROW(check_texture_size(kMinTextureSize, 1 << 20, true));
    EXPECT_NO_THROW(check_texture_size(kDefaultMaxImageDimension, kDefaultMaxImageDimension, true));
    EXPECT_NO_THROW(check_texture_size(2048, 1024, false));  // no built-in set made at that size
    expect_error([] { check_texture_size(3, 1024, true); }, "texture_size",
                 "must be in [4, 1024] ('max_size'), got 3");
    expect_error([] { check_texture_size(8192, 1024, true); }, "texture_size",
                 "must be in [4, 1024] ('max_size'), got 8192");
    expect_error([] { check_texture_size(20000, 1 << 20, true); }, "texture_size",
                 "must be in [4, 16384], got 20000");
}

LayerSettings two_layers() {
    LayerSettings layers;
    layers.sources = {"bumps", "noise"};
    return layers;
}

TEST(LayerSettings, DefaultsFillEveryLayer) {
    const LayerSettings layers = two_layers();
    EXPECT_NO_THROW(validate(layers));
    EXPECT_NO_THROW(validate(LayerSettings{}));  // no layers: the one map of the bump source
    const LayerBlend blend = layer_blend(layers);
    EXPECT_EQ(blend.weights, (std::vector<float>{0.5f, 0.5f}));
    EXPECT_EQ(blend.strengths, (std::vector<float>{1.0f, 1.0f}));
    EXPECT_EQ(layer_tilings(layers), (std::vector<float>{1.0f, 1.0f}));
    EXPECT_EQ(layer_velocities(layers), (std::vector<glm::vec2>(2, glm::vec2(0.0f))));
    LayerSettings given = layers;
    given.weights = {0.25f, 0.75f};
    given.tiling = {1.0f, 3.0f};
    EXPECT_EQ(layer_blend(given).weights, given.weights);
    EXPECT_EQ(layer_tilings(given), given.tiling);
}

TEST(LayerSettings, CountsAndRangesNameTheirSettings) {
    const struct {
        void (*change)(LayerSettings&);
        const char* setting;
        const char* part;
    } cases[] = {
        {[](LayerSettings& l) { l.sources = {"bumps"}; }, "layers", "2 to 4 sources, got 1"},
        {[](LayerSettings& l) {
             l.sources = {"a", "b", "c", "d", "e"};
         },
         "layers", "got 5"},
        {[](LayerSettings& l) {
             l.sources = {"bumps", ""};
         },
         "layers", "source 2 of 2 is empty ('bumps,')"},
        {[](LayerSettings& l) { l.weights = {1.0f}; }, "layer-weights",
         "one value per layer: 2 layers, 1 values"},
        {[](LayerSettings& l) {
             l.weights = {0.3f, 0.3f};
         },
         "layer-weights", "sum to 1"},
        {[](LayerSettings& l) {
             l.strengths = {1.0f, 0.0f};
         },
         "layer-strengths", "non-zero"},
        {[](LayerSettings& l) {
             l.tiling = {1.0f, -2.0f};
         },
         "layer-tiling", "each tiling must be in (0, 1e+06], as 'tiling', got -2"},
        {[](LayerSettings& l) {
             l.tiling = {1.0f, 2.0f, 3.0f};
         },
         "layer-tiling", "3 values"},
        {[](LayerSettings& l) {
             l.velocity = {{1e30f, 0.0f}, {0.0f, 0.0f}};
         },
         "layer-velocity", "each component must be in [-1e+06, 1e+06]"},
        {[](LayerSettings& l) {
             l.velocity = {{0.0f, 0.0f}};
         },
         "layer-velocity", "one U:V per layer"},
    };
    for (const auto& c : cases) {
        LayerSettings layers = two_layers();
        c.change(layers);
        SCOPED_TRACE(c.part);
        expect_error([&] { validate(layers); }, c.setting, c.part);
    }
}

TEST(PresetLayers, LayersMapsAndTechniquesRoundTripTyped) {
    Preset p;
    p.layers.sources = {"bumps", "noise", "ridges.png"};
    p.layers.weights = {0.2f, 0.3f, 0.5f};
    p.layers.strengths = {1.0f, -0.5f, 2.0f};
    p.layers.tiling = {1.0f, 2.0f, 0.25f};
    p.layers.velocity = {{0.02f, 0.0f}, {-0.01f, 0.03f}, {0.0f, 0.0f}};
    p.layers.weight_map = "weights.png";
    p.layers.mixing = LayerMixing::Approx;
    p.maps = {{"roughness_map", "rough.png"}};
    p.bumps.from = BakeSource::Height;
    p.bumps.bits = StoragePolicy::fixed(Storage::Unorm8);
    p.techniques = {Technique::Lean, Technique::Roughness};
    p.layout = PaneLayout::Split;
    const std::string text = preset_to_json(p);
    const Preset back = preset_from_json(text, "layers.json");
    EXPECT_EQ(back.layers, p.layers);
    EXPECT_EQ(back.maps, p.maps);
    EXPECT_EQ(back.bumps, p.bumps);
    EXPECT_EQ(back.techniques, p.techniques);
    EXPECT_EQ(back.layout, PaneLayout::Split);
    EXPECT_EQ(preset_to_json(back), text);
    EXPECT_NE(text.find("\"mixing\": \"approx\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"techniques\": [\n      \"lean\",\n      \"roughness\""),
              std::string::npos)
        << text;
}

TEST(PresetLayers, BadLayersMapsAndNamesNameTheirKeys) {
    const struct {
        const char* text;
        const char* key;
        const char* part;
    } cases[] = {
        {R"({"layers": {"sources": ["bumps"]}})", "layers.sources", "2 to 4 sources"},
        {R"({"layers": {"sources": ["bumps", "noise"], "weights": [0.3, 0.3]}})", "layers.weights",
         "sum to 1"},
        {R"({"layers": {"sources": ["bumps", "noise"], "tiling": [1, 0]}})", "layers.tiling",
         "(0, 1e+06]"},
        {R"({"layers": {"sources": ["bumps", "noise"], "velocity": [[1, 0], [2]]}})",
         "layers.velocity[1]", "2 numbers"},
        {R"({"layers": {"mixing": "blend"}})", "layers.mixing", "unknown mixing method 'blend'"},
        {R"({"layers": {"colour": 1}})", "layers.colour", "unknown key"},
        {R"({"maps": {"roughness_map": ""}})", "maps.roughness_map", "empty"},
        {R"({"maps": {"roughness_map": 3}})", "maps.roughness_map", "expected a string"},
        {R"({"bumps": {"from": "heightmap"}})", "bumps.from", "heightmap"},
        {R"({"view": {"techniques": ["phong"]}})", "view.techniques", "unknown technique 'phong'"},
        {R"({"view": {"techniques": [""]}})", "view.techniques", "empty"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.text);
        try {
            preset_from_json(c.text, "bad.json");
            ADD_FAILURE() << "accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), "bad.json");
            EXPECT_NE(e.cause().find(std::string("key '") + c.key + "'"), std::string::npos)
                << e.what();
            EXPECT_NE(e.cause().find(c.part), std::string::npos) << e.what();
        }
    }
}

TEST(PaneLayouts, NamesAndPaneCounts) {
    for (std::size_t i = 0; i < preset_layouts().size(); ++i) {
        const PaneLayout layout = parse_pane_layout(preset_layouts()[i]);
        EXPECT_EQ(std::size_t(layout), i);
        EXPECT_EQ(to_string(layout), preset_layouts()[i]);
    }
    EXPECT_TRUE(layout_accepts(PaneLayout::Single, 1));
    EXPECT_FALSE(layout_accepts(PaneLayout::Single, 2));
    EXPECT_TRUE(layout_accepts(PaneLayout::Split, 2));
    EXPECT_FALSE(layout_accepts(PaneLayout::Split, 3));
    EXPECT_TRUE(layout_accepts(PaneLayout::SideBySide, 3));
    EXPECT_FALSE(layout_accepts(PaneLayout::SideBySide, 1));
    expect_error([] { parse_pane_layout("grid", "--layout"); }, "--layout",
                 "expected single, split or side-by-side, got 'grid'");
}

}  // namespace
}  // namespace leanfade
