// The surface-map table (leanfade/scene/detail/map_kinds.hpp) and the scene rules derived from it:
// every kind has its own unit and mask bit, and validate() holds each kind's textures to the
// kind's channels and MIP rule and each material's slots to the scene's textures.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "leanfade/core/detail/bindings.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/scene/detail/generators.hpp"
#include "leanfade/scene/material.hpp"

namespace leanfade::scene {
namespace {

TEST(MapKinds, EachKindHasItsOwnUnitBitAndName) {
    std::set<int> units, bits;
    std::set<std::string_view> names;
    for (const MapKindInfo& kind : kMapKinds) {
        EXPECT_TRUE(units.insert(kind.binding).second) << kind.name;
        EXPECT_TRUE(bits.insert(kind.mask_bit).second) << kind.name;
        EXPECT_TRUE(names.insert(kind.name).second) << kind.name;
        // One bit each, and not the LEAN map's unit.
        EXPECT_EQ(kind.mask_bit & (kind.mask_bit - 1), 0) << kind.name;
        EXPECT_GT(kind.mask_bit, 0) << kind.name;
        // Not a unit of the LEAN map or the bump layers (bindings.glsl).
        EXPECT_NE(kind.binding, bindings::LF_BINDING_LEAN_MAP) << kind.name;
        EXPECT_TRUE(kind.binding < bindings::LF_BINDING_LAYER_MAPS ||
                    kind.binding > bindings::LF_BINDING_LAYER_WEIGHTS)
            << kind.name;
        EXPECT_FALSE(kind.glsl_name.empty()) << kind.name;
        EXPECT_TRUE(kind.channels == 1 || kind.channels == 4) << kind.name;
        EXPECT_FALSE(kind.meaning.empty()) << kind.name;
        EXPECT_EQ(&info(kind.kind), &kind);
    }
}

// shaders/map_kinds.glsl and map_samplers.glsl are what the table generates (run with
// LEANFADE_UPDATE_SHADER_TABLES=1, as `make shader-tables` does, to write them again).
TEST(MapKinds, ShaderFilesAreTheTable) {
    const std::pair<std::string, std::string> files[] = {
        {"map_kinds.glsl", map_kinds_glsl()}, {"map_samplers.glsl", map_samplers_glsl()}};
    for (const auto& [name, text] : files) {
        const std::string path = std::string(LEANFADE_SOURCE_DIR) + "/shaders/" + name;
        if (std::getenv("LEANFADE_UPDATE_SHADER_TABLES") != nullptr)
            std::ofstream(path, std::ios::binary) << text;
        std::ifstream in(path, std::ios::binary);
        std::stringstream stored;
        stored << in.rdbuf();
        EXPECT_EQ(stored.str(), text) << path << " is not the table's: run `make shader-tables`";
    }
    // The shaders' constants (bindings.glsl's C++ view includes map_kinds.glsl) are the rows'.
    EXPECT_EQ(bindings::LF_BINDING_PLATEAU, info(MapKind::Plateau).binding);
    EXPECT_EQ(bindings::LF_MAP_PLATEAU, info(MapKind::Plateau).mask_bit);
    EXPECT_EQ(bindings::LF_BINDING_ROUGHNESS_MIPS, info(MapKind::RoughnessMips).binding);
    EXPECT_EQ(bindings::LF_MAP_BASE_COLOR, info(MapKind::BaseColor).mask_bit);
    // Every row's sampler, named from the row, once; a variant's map within its #if.
    const std::string samplers = map_samplers_glsl();
    for (const MapKindInfo& kind : kMapKinds) {
        std::string sampler = "u_" + std::string(kind.glsl_name);
        for (char& c : sampler) c = char(std::tolower(static_cast<unsigned char>(c)));
        const std::size_t at = samplers.find("uniform sampler2D " + sampler + ";");
        ASSERT_NE(at, std::string::npos) << sampler;
        EXPECT_EQ(samplers.find("uniform sampler2D " + sampler + ";", at + 1), std::string::npos);
        if (!kind.variant_define.empty()) {
            EXPECT_NE(samplers.rfind("#if defined(" + std::string(kind.variant_define) + ")\n", at),
                      std::string::npos)
                << sampler;
        }
    }
}

Scene one_object_scene() {
    Scene scene;
    scene.objects.push_back({make_sphere(8, 4), 0, glm::mat4(1.0f)});
    scene.materials.push_back(Material{});
    scene.lean_maps.push_back(PackedLeanMap{});
    return scene;
}

TEST(MapKinds, ValidateHoldsEveryKindToItsRules) {
    for (const MapKindInfo& kind : kMapKinds) {
        // A good texture of the kind: level 0 for Generated, the full chain for Given.
        std::vector<Image> good{Image(4, 4, kind.channels, 0.5f)};
        if (kind.mips == MapMips::Given)
            good = kind.channels == 1 ? base_alpha_squared_mips(Image(4, 4, 1, 0.5f))
                                      : build_mip_chain(Image(4, 4, kind.channels, 0.5f));
        Scene scene = one_object_scene();
        scene.materials[0].map(kind.kind) = scene.add_map(kind.kind, good);
        EXPECT_NO_THROW(validate(scene)) << kind.name;

        Scene slot = scene;
        slot.materials[0].map(kind.kind) = 1;  // only texture 0 exists
        EXPECT_THROW(validate(slot), Error) << kind.name;

        Scene channels = scene;
        for (Image& level : channels.maps_of(kind.kind)[0])
            level = Image(level.width, level.height, kind.channels == 1 ? 4 : 1, 0.5f);
        EXPECT_THROW(validate(channels), Error) << kind.name;

        Scene levels = scene;
        if (kind.mips == MapMips::Given)
            levels.maps_of(kind.kind)[0].pop_back();  // a chain that stops before 1x1
        else
            levels.maps_of(kind.kind)[0].push_back(Image(2, 2, kind.channels, 0.5f));
        EXPECT_THROW(validate(levels), Error) << kind.name;

        Scene nan = scene;
        nan.maps_of(kind.kind)[0][0].pixels[0] = std::numeric_limits<float>::quiet_NaN();
        EXPECT_THROW(validate(nan), Error) << kind.name;
    }
}

TEST(MapKinds, ANegativeAlphaSquaredIsRefused) {
    Scene scene = one_object_scene();
    std::vector<Image> chain = base_alpha_squared_mips(Image(4, 4, 1, 0.5f));
    chain[0].pixels[3] = -0.25f;
    scene.materials[0].map(MapKind::BaseRoughness) =
        scene.add_map(MapKind::BaseRoughness, std::move(chain));
    try {
        validate(scene);
        FAIL() << "a negative alpha0^2 must be refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "roughness-map");
        EXPECT_NE(e.cause().find(">= 0"), std::string::npos) << e.what();
    }
}

TEST(MapKinds, MaterialsStartWithEverySlotEmpty) {
    const Material material;
    for (const MapKindInfo& kind : kMapKinds) EXPECT_EQ(material.map(kind.kind), -1);
}

}  // namespace
}  // namespace leanfade::scene
