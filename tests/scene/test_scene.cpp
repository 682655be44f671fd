// The by-name dispatcher.
#include <string>

#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::scene {
namespace {

TEST(SceneNames, FixedList) {
    const std::vector<std::string> expected = {"sphere", "torus", "teapot", "terrain", "plane"};
    EXPECT_EQ(builtin_scene_names(), expected);
}

TEST(SceneNames, EachBuiltinBuildsItsDefault) {
    for (const std::string& name : builtin_scene_names()) {
        const Mesh m = make_scene_mesh(name);
        EXPECT_EQ(m.name, name);
        EXPECT_GT(m.triangle_count(), 0u);
    }
    EXPECT_EQ(make_scene_mesh("sphere").triangle_count(), make_sphere().triangle_count());
    EXPECT_EQ(make_scene_mesh("plane").triangle_count(), make_plane(20.0f, 64).triangle_count());
    const Mesh a = make_scene_mesh("terrain");
    const Mesh b = make_terrain(1);
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    EXPECT_EQ(a.vertices.back().position, b.vertices.back().position);
}

TEST(SceneNames, UnknownNameListsTheValidOnes) {
    for (const std::string bad : {"cube", "Sphere", "", "teapot.ob"}) {
        try {
            (void)make_scene_mesh(bad);
            ADD_FAILURE() << "no error for '" << bad << "'";
        } catch (const leanfade::Error& e) {
            EXPECT_EQ(e.file(), bad);
            for (const std::string& name : builtin_scene_names()) {
                EXPECT_NE(e.cause().find(name), std::string::npos) << e.what();
            }
            EXPECT_NE(e.cause().find(".obj"), std::string::npos) << e.what();
        }
    }
}

TEST(SceneNames, MissingObjPathIsAnError) {
    EXPECT_THROW(make_scene_mesh("/nonexistent/dir/model.obj"), leanfade::Error);
}

}  // namespace
}  // namespace leanfade::scene
