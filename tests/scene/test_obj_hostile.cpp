// Hostile OBJ files (docs/robustness.md): what fuzz_obj and the hostile-file matrix found.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/obj_loader.hpp"

namespace leanfade::scene {
namespace {

std::filesystem::path scratch() {
    const auto dir = std::filesystem::path(LEANFADE_TEST_TMP) / "scene_hostile";
    std::filesystem::create_directories(dir);
    return dir;
}

void expect_error(const std::string& path, const std::string& text, const std::string& cause) {
    try {
        (void)load_obj_from_memory(text, path);
        ADD_FAILURE() << path << ": no error thrown";
    } catch (const leanfade::Error& e) {
        EXPECT_EQ(e.file(), path);
        EXPECT_NE(e.cause().find(cause), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
}

// tinyobjloader parses numbers itself, differently from strtod, which checks them: "0x10" (16)
// became 0, and the exponent of "0e2147483649" (0) overflowed an int (undefined behaviour, caught
// by `make sanitize`, where tinyobjloader is instrumented). The loader now hands it the checked
// values, so the mesh holds what strtod read.
TEST(ObjHostile, NumbersAreTheCheckedValues) {
    const Mesh mesh = load_obj_from_memory(
        "v 0e400 0x10 1e-2\nv 1 0 0e2147483649\nv +0.5 1 -0\nf 1 2 3\n", "numbers.obj");
    ASSERT_EQ(mesh.vertices.size(), 3u);
    EXPECT_EQ(mesh.vertices[0].position.x, 0.0f);
    EXPECT_EQ(mesh.vertices[0].position.y, 16.0f);
    EXPECT_FLOAT_EQ(mesh.vertices[0].position.z, 0.01f);
    EXPECT_EQ(mesh.vertices[1].position.z, 0.0f);
    EXPECT_EQ(mesh.vertices[2].position.x, 0.5f);
    for (const Vertex& v : mesh.vertices) {
        EXPECT_TRUE(std::isfinite(v.tangent.x) && std::isfinite(v.normal.x));
    }
}

// Found by fuzz_obj (UBSan in tinyobjloader: an infinite joint id of a "vw" skin-weight line
// converted to int). Lines leanfade does not use never reach tinyobjloader.
TEST(ObjHostile, IgnoredLinesWithHostileValuesDoNotMatter) {
    const Mesh mesh = load_obj_from_memory(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvw 0 1e39 0.5\n"
        "vw 1 -nan inf\nl 1 99999999999\np -7\n"
        "s 1e99\ng \xa0\xff\nusemtl \x01\nf 1 2 3\n",
        "ignored.obj");
    EXPECT_EQ(mesh.triangle_count(), 1u);
}

TEST(ObjHostile, FaceVertexWithFourPartsIsMalformed) {
    expect_error("parts.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1/1 2 3\n",
                 "line 6: malformed face vertex '1/1/1/1'");
}

// Found by the hostile-file matrix: reading a FIFO without a writer blocked forever. A writer is
// held here, so that the test cannot block either way.
TEST(ObjHostile, FifoIsNotARegularFile) {
    const std::string path = (scratch() / "pipe.obj").string();
    std::filesystem::remove(path);
    ASSERT_EQ(::mkfifo(path.c_str(), 0644), 0);
    const int holder = ::open(path.c_str(), O_RDWR | O_NONBLOCK);
    ASSERT_GE(holder, 0);
    try {
        (void)load_obj(path);
        ADD_FAILURE() << "no error thrown";
    } catch (const leanfade::Error& e) {
        EXPECT_EQ(e.cause(), "is not a regular file");
    }
    ::close(holder);
}

TEST(ObjHostile, LoadFromMemoryMatchesLoadFromFile) {
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
        "vt 0 1\nf 1/1 2/2 3/3 4/4\n";
    const std::string path = (scratch() / "quad.obj").string();
    std::ofstream(path, std::ios::binary) << text;
    const Mesh from_file = load_obj(path);
    const Mesh from_memory = load_obj_from_memory(text, path);
    EXPECT_EQ(from_memory.name, "quad");
    EXPECT_EQ(from_memory.indices, from_file.indices);
    ASSERT_EQ(from_memory.vertices.size(), from_file.vertices.size());
    for (std::size_t i = 0; i < from_file.vertices.size(); ++i) {
        EXPECT_EQ(from_memory.vertices[i].position, from_file.vertices[i].position);
        EXPECT_EQ(from_memory.vertices[i].uv, from_file.vertices[i].uv);
    }
}

}  // namespace
}  // namespace leanfade::scene
