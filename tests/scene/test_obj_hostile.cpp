// Hostile OBJ files (docs/robustness.md): what fuzz_obj and the hostile-file matrix found.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/scene/detail/obj_loader.hpp"

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

// A convex polygon of `count` vertices on the unit circle (z = 0), as one face; `dented`: its
// middle vertex pulled in to radius 0.5 (a non-convex polygon).
std::string disc(std::size_t count, bool dented = false) {
    std::string text;
    for (std::size_t i = 0; i < count; ++i) {
        const double angle = 6.283185307179586 * double(i) / double(count);
        const double radius = dented && i == count / 2 ? 0.5 : 1.0;
        char line[64];
        std::snprintf(line, sizeof line, "v %.9g %.9g 0\n", radius * std::cos(angle),
                      radius * std::sin(angle));
        text += line;
    }
    text += "f";
    for (std::size_t i = 1; i <= count; ++i) text.append(1, ' ').append(std::to_string(i));
    return text + "\n";
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A star polygon of `points` tips (2 * points vertices, non-convex), as one face.
std::string star(std::size_t points) {
    std::string text;
    for (std::size_t i = 0; i < 2 * points; ++i) {
        const double angle = 3.141592653589793 * double(i) / double(points);
        const double radius = i % 2 == 0 ? 1.0 : 0.5;
        text.append("v ").append(std::to_string(radius * std::cos(angle))).append(" ");
        text.append(std::to_string(radius * std::sin(angle))).append(" 0\n");
    }
    text += "f";
    for (std::size_t i = 1; i <= 2 * points; ++i) text.append(1, ' ').append(std::to_string(i));
    return text + "\n";
}

// Sum of the triangles' signed areas in the z = 0 plane (counter-clockwise positive).
double signed_area(const Mesh& mesh) {
    double area = 0.0;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const glm::vec3 a = mesh.vertices[mesh.indices[t]].position;
        const glm::vec3 b = mesh.vertices[mesh.indices[t + 1]].position;
        const glm::vec3 c = mesh.vertices[mesh.indices[t + 2]].position;
        area += 0.5 * (double(b.x - a.x) * double(c.y - a.y) -
                       double(b.y - a.y) * double(c.x - a.x));
    }
    return area;
}

// Found by an outside probe: tinyobjloader triangulates a polygon in time quadratic in its
// vertex count, so one face of 100 000 vertices (2 MB of text) took more than 30 s. Faces are
// triangulated by the loader now: up to 64 vertices by ear clipping (right for non-convex faces),
// larger ones as fans (linear time). The bound below is a hang guard, not a speed measurement:
// 300 000 vertices load in about 2 s here, while quadratic triangulation takes minutes (at
// 100 000 vertices it already took more than 30 s).
TEST(ObjHostile, FaceWithHundredThousandVerticesLoadsInLinearTime) {
    for (const bool dented : {false, true}) {
        const auto start = std::chrono::steady_clock::now();
        const Mesh mesh = load_obj_from_memory(disc(300000, dented), "big_face.obj");
        EXPECT_LT(seconds_since(start), 60.0);
        EXPECT_EQ(mesh.triangle_count(), 299998u);
        if (!dented) {
            EXPECT_NEAR(signed_area(mesh), 3.141592653589793, 1e-3);  // all CCW
        }
    }

    // A non-convex star of 64 vertices: ear-clipped into 62 triangles covering exactly the star
    // (a fan from vertex 0 would cover some of it twice and leave the area wrong).
    const Mesh clipped = load_obj_from_memory(star(32), "star.obj");
    EXPECT_EQ(clipped.triangle_count(), 62u);
    const double star_area = 32 * 2 * 0.5 * 1.0 * 0.5 * std::sin(3.141592653589793 / 32);
    EXPECT_NEAR(signed_area(clipped), star_area, 1e-5);
}

// Found by an outside probe: text of the file reached messages raw. A malformed token with a
// terminal escape sequence and a newline is escaped in the one-line message.
TEST(ObjHostile, FileTextInMessagesIsEscaped) {
    expect_error("escape.obj", "v 0 0 \x1b[31mred\n",
                 "line 1: '\\x1B[31mred' is not a number");
}

// Found by an outside probe (for `--preset`; OBJ files went through the same kind of reader):
// a directory, a FIFO and a device are refused by the one reader of text files, without reading.
TEST(ObjHostile, DeviceAndDirectoryAreRefusedWithoutReading) {
    try {
        (void)load_obj("/dev/zero");
        ADD_FAILURE() << "no error thrown";
    } catch (const leanfade::Error& e) {
        EXPECT_EQ(e.cause(), "is not a regular file");
    }
    try {
        (void)load_obj(scratch().string());
        ADD_FAILURE() << "no error thrown";
    } catch (const leanfade::Error& e) {
        EXPECT_EQ(e.cause(), "is a directory, not an OBJ file");
    }
}

// Before: the .mtl and texture names of an OBJ were confined by their spelling only, so a
// symbolic link inside the OBJ's folder to a file outside it was followed and the outside file's
// text (here a "newmtl" line) reached the messages. Where each name leads is checked before any
// byte is read; a link that stays inside the folder is still followed.
TEST(ObjHostile, LinksOutOfTheObjsFolderAreRefusedBeforeReading) {
    namespace fs = std::filesystem;
    const fs::path root = scratch() / "links";
    fs::remove_all(root);
    fs::create_directories(root / "scene");
    fs::create_directories(root / "outside");
    const std::string secret = "SECRET-LINE-OF-AN-OUTSIDE-FILE";
    std::ofstream(root / "outside" / "secret.mtl") << "newmtl A\nKd 1 " << secret << " 1\n";
    std::ofstream(root / "outside" / "secret.png") << secret;
    std::ofstream(root / "scene" / "real.mtl") << "newmtl A\nKd 1 1 1\n";
    fs::create_symlink("../outside/secret.mtl", root / "scene" / "out.mtl");
    fs::create_symlink(root / "outside" / "secret.mtl", root / "scene" / "absolute.mtl");
    fs::create_symlink("../outside", root / "scene" / "sub");
    fs::create_symlink("real.mtl", root / "scene" / "in.mtl");
    fs::create_symlink("../outside/secret.png", root / "scene" / "out.png");
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n";
    const auto scene_of = [&](const std::string& obj_text, const std::string& mtl_text) {
        if (!mtl_text.empty()) std::ofstream(root / "scene" / "m.mtl") << mtl_text;
        std::ofstream(root / "scene" / "m.obj") << obj_text;
        ObjBakeSettings settings;
        return make_obj_render_scene(load_obj_model((root / "scene" / "m.obj").string()),
                                     settings);
    };
    const struct {
        std::string obj, mtl, file, cause;
    } cases[] = {
        {"mtllib out.mtl\nusemtl A\n" + quad, "", "m.obj",
         "mtllib 'out.mtl' resolves outside the OBJ's folder"},
        {"mtllib absolute.mtl\nusemtl A\n" + quad, "", "m.obj",
         "mtllib 'absolute.mtl' resolves outside the OBJ's folder"},
        {"mtllib sub/secret.mtl\nusemtl A\n" + quad, "", "m.obj",
         "mtllib 'sub/secret.mtl' resolves outside the OBJ's folder"},
        {"mtllib m.mtl\nusemtl A\n" + quad, "newmtl A\nmap_Kd out.png\n", "m.mtl",
         "map_Kd 'out.png' resolves outside the OBJ's folder"},
        {"mtllib m.mtl\nusemtl A\n" + quad, "newmtl A\nnorm sub/secret.png\n", "m.mtl",
         "norm 'sub/secret.png' resolves outside the OBJ's folder"},
        {"mtllib m.mtl\nusemtl A\n" + quad, "newmtl A\nmap_Bump out.png\n", "m.mtl",
         "map_Bump 'out.png' resolves outside the OBJ's folder"},
        {"mtllib m.mtl\nusemtl A\n" + quad, "newmtl A\nmap_Pr out.png\n", "m.mtl",
         "map_Pr 'out.png' resolves outside the OBJ's folder"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.cause);
        try {
            (void)scene_of(c.obj, c.mtl);
            ADD_FAILURE() << "no error";
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), (root / "scene" / c.file).string());
            EXPECT_NE(e.cause().find(c.cause), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).find(secret), std::string::npos) << e.what();
        }
    }
    // A link that stays inside the folder is followed.
    const Scene inside = scene_of("mtllib in.mtl\nusemtl A\n" + quad, "");
    ASSERT_EQ(inside.materials.size(), 1u);
    EXPECT_EQ(inside.materials[0].name, "A");
}

// Blender's OBJ exporter writes a normal map as map_Bump: a colour image where a height map is
// expected is baked as the normal map it is (bake's content rule), with a warning; a grey one
// stays a height map.
TEST(ObjMaterials, ColourMapBumpIsBakedAsANormalMap) {
    namespace fs = std::filesystem;
    const fs::path root = scratch() / "map_bump_normal";
    fs::remove_all(root);
    fs::create_directories(root);
    Image normals(32, 32, 3);
    Image heights(32, 32, 1);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const glm::vec3 n = glm::normalize(
                glm::vec3(0.3f * std::sin(0.4f * float(x)), 0.2f * std::cos(0.3f * float(y)), 1.0f));
            for (int c = 0; c < 3; ++c) normals.at(x, y, c) = 0.5f * n[c] + 0.5f;
            heights.at(x, y) = 0.5f + 0.3f * std::sin(0.4f * float(x));
        }
    io::write_png((root / "n.png").string(), normals, 8);
    io::write_png((root / "h.png").string(), heights, 8);
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n";
    std::ofstream(root / "m.obj") << "mtllib m.mtl\nusemtl A\n" + quad;
    const auto scene_of = [&](const std::string& mtl_text, ObjSceneReport& report) {
        std::ofstream(root / "m.mtl") << mtl_text;
        return make_obj_render_scene(load_obj_model((root / "m.obj").string()), {}, &report);
    };
    ObjSceneReport as_bump, as_norm, as_height;
    const Scene bump = scene_of("newmtl A\nmap_Bump n.png\n", as_bump);
    const Scene norm = scene_of("newmtl A\nnorm n.png\n", as_norm);
    ASSERT_EQ(bump.lean_maps.size(), 1u);
    ASSERT_EQ(norm.lean_maps.size(), 1u);
    for (std::size_t l = 0; l < norm.lean_maps[0].levels.size(); ++l)
        EXPECT_TRUE(bump.lean_maps[0].levels[l].lean2 == norm.lean_maps[0].levels[l].lean2) << l;
    ASSERT_EQ(as_bump.warnings.size(), 1u);
    EXPECT_NE(as_bump.warnings[0].find("map_Bump n.png is a colour image"), std::string::npos)
        << as_bump.warnings[0];
    EXPECT_TRUE(as_norm.warnings.empty());
    // A grey map_Bump is a height map, as before.
    const Scene height = scene_of("newmtl A\nmap_Bump -bm 2 h.png\n", as_height);
    EXPECT_TRUE(as_height.warnings.empty());
    ASSERT_EQ(height.lean_maps.size(), 1u);
    EXPECT_FALSE(height.lean_maps[0].levels[0].lean2 == norm.lean_maps[0].levels[0].lean2);
}

}  // namespace
}  // namespace leanfade::scene
