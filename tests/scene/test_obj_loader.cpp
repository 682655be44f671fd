// OBJ loading: files written into LEANFADE_TEST_TMP by the tests themselves.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/detail/obj_loader.hpp"
#include "leanfade/scene/detail/scene.hpp"
#include "mesh_checks.hpp"

namespace leanfade::scene {
namespace {

std::string write_obj(const std::string& name, const std::string& text) {
    const std::filesystem::path dir = std::filesystem::path(LEANFADE_TEST_TMP) / "scene";
    std::filesystem::create_directories(dir);
    const std::filesystem::path path = dir / name;
    std::ofstream out(path, std::ios::binary);
    out << text;
    return path.string();
}

const char* const kCubePositions =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n";

// A unit cube, quads CCW seen from outside, each face's UV square right-handed with its normal.
std::string cube_with_normals_and_uvs() {
    return std::string("# cube\no cube\n") + kCubePositions +
           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
           "vn 0 0 1\nvn 0 0 -1\nvn 1 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\n"
           "f 5/1/1 6/2/1 7/3/1 8/4/1\n"
           "f 2/1/2 1/2/2 4/3/2 3/4/2\n"
           "f 6/1/3 2/2/3 3/3/3 7/4/3\n"
           "f 1/1/4 5/2/4 8/3/4 4/4/4\n"
           "f 8/1/5 7/2/5 3/3/5 4/4/5\n"
           "f 1/1/6 2/2/6 6/3/6 5/4/6\n";
}

std::string cube_positions_only() {
    return std::string(kCubePositions) +
           "f 5 6 7 8\nf 2 1 4 3\nf 6 2 3 7\nf 1 5 8 4\nf 8 7 3 4\nf 1 2 6 5\n";
}

void expect_sound(const Mesh& m) {
    ASSERT_TRUE(test::indices_valid(m));
    const auto f = test::frame_stats(m);
    EXPECT_EQ(f.non_finite, 0u);
    EXPECT_LT(f.max_normal_error, 1e-5f);
    EXPECT_LT(f.max_tangent_error, 1e-5f);
    EXPECT_LT(f.max_tangent_dot_normal, 1e-5f);
    EXPECT_EQ(f.bad_handedness, 0u);
    Mesh copy = m;
    compute_bounds(copy);
    EXPECT_EQ(copy.bounds.min, m.bounds.min);
    EXPECT_EQ(copy.bounds.max, m.bounds.max);
}

TEST(LoadObj, CubeWithNormalsAndUvs) {
    const Mesh m = load_obj(write_obj("cube_full.obj", cube_with_normals_and_uvs()));
    EXPECT_EQ(m.name, "cube_full");
    EXPECT_EQ(m.triangle_count(), 12u);
    EXPECT_EQ(m.vertices.size(), 24u);  // 6 faces x 4 corners, each with its own normal
    expect_sound(m);
    EXPECT_EQ(m.bounds.min, glm::vec3(-0.5f));
    EXPECT_EQ(m.bounds.max, glm::vec3(0.5f));
    EXPECT_NEAR(test::signed_volume(m), 1.0, 1e-6);
    const auto e = test::edge_stats(m);
    EXPECT_EQ(e.boundary, 0u);
    EXPECT_EQ(e.same_direction, 0u);
    EXPECT_EQ(e.paired, 18u);
    const auto w = test::winding_stats(m);
    EXPECT_EQ(w.disagreeing, 0u);
    EXPECT_GT(w.min_dot, 0.99999f);  // file normals are the face normals
    const auto u = test::uv_frame_stats(m);
    EXPECT_EQ(u.corners, 36u);
    EXPECT_GT(u.min_cos_tangent, 0.99999f);
    EXPECT_GT(u.min_cos_bitangent, 0.99999f);
    EXPECT_EQ(test::frame_stats(m).left_handed, 0u);
    // +z face: u along +x.
    for (const Vertex& v : m.vertices) {
        if (v.normal.z > 0.5f) {
            EXPECT_NEAR(v.tangent.x, 1.0f, 1e-6f);
            EXPECT_NEAR(v.uv.x, v.position.x + 0.5f, 1e-6f);
        }
    }
}

TEST(LoadObj, CubeWithoutNormalsOrUvs) {
    const Mesh m = load_obj(write_obj("cube_bare.obj", cube_positions_only()));
    EXPECT_EQ(m.triangle_count(), 12u);
    EXPECT_EQ(m.vertices.size(), 24u);  // split by box-projection axis
    expect_sound(m);
    // Area-weighted smooth normals: outward, the same for all copies of a corner.
    for (const Vertex& v : m.vertices) {
        EXPECT_GT(glm::dot(v.normal, glm::normalize(v.position)), 0.5f);
        for (const Vertex& o : m.vertices) {
            if (o.position == v.position) {
                EXPECT_EQ(o.normal, v.normal);
            }
        }
    }
    EXPECT_NEAR(test::signed_volume(m), 1.0, 1e-6);
    // Box projection: UVs in [0, 1], right-handed with the face, every face a full tile.
    for (const Vertex& v : m.vertices) {
        EXPECT_GE(v.uv.x, 0.0f);
        EXPECT_LE(v.uv.x, 1.0f);
        EXPECT_GE(v.uv.y, 0.0f);
        EXPECT_LE(v.uv.y, 1.0f);
    }
    const auto u = test::uv_frame_stats(m);
    EXPECT_EQ(u.corners, 36u);
    EXPECT_EQ(u.tangent_opposed, 0u);
    EXPECT_EQ(u.bitangent_opposed, 0u);
    EXPECT_EQ(test::frame_stats(m).left_handed, 0u);
}

TEST(LoadObj, PolygonsAreTriangulated) {
    const std::string quad = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nf 1 2 3 4\n";
    const Mesh q = load_obj(write_obj("quad.obj", quad));
    EXPECT_EQ(q.triangle_count(), 2u);
    EXPECT_EQ(q.vertices.size(), 4u);
    expect_sound(q);
    for (const Vertex& v : q.vertices) {
        EXPECT_NEAR(v.normal.z, 1.0f, 1e-6f);
        EXPECT_NEAR(v.uv.x, v.position.x / 2.0f, 1e-6f);  // +z projection, largest extent 2
        EXPECT_NEAR(v.uv.y, v.position.y / 2.0f, 1e-6f);
        EXPECT_NEAR(v.tangent.x, 1.0f, 1e-6f);
    }
    EXPECT_EQ(test::winding_stats(q).disagreeing, 0u);

    // A pentagon with relative (negative) indices and a UV-only corner format.
    const std::string pentagon =
        "v 0 0 0\nv 1 0 0\nv 1.3 1 0\nv 0.5 1.6 0\nv -0.3 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1.3 1\nvt 0.5 1.6\nvt -0.3 1\n"
        "f -5/-5 -4/-4 -3/-3 -2/-2 -1/-1\n";
    const Mesh p = load_obj(write_obj("pentagon.obj", pentagon));
    EXPECT_EQ(p.triangle_count(), 3u);
    EXPECT_EQ(p.vertices.size(), 5u);
    expect_sound(p);
    EXPECT_NEAR(test::signed_volume(p), 0.0, 1e-9);
    EXPECT_EQ(test::winding_stats(p).disagreeing, 0u);
}

TEST(LoadObj, SeveralObjectsBecomeOneMesh) {
    const std::string text = std::string(kCubePositions) +
                             "o a\nf 5 6 7 8\nf 2 1 4 3\ng b\nf 6 2 3 7\nf 1 5 8 4\n"
                             "usemtl missing\nf 8 7 3 4\nf 1 2 6 5\n";
    const Mesh m = load_obj(write_obj("groups.obj", text));
    EXPECT_EQ(m.triangle_count(), 12u);
    expect_sound(m);
}

TEST(LoadObj, CommentsAndWindowsLineEndings) {
    const std::string text =
        "# a quad\r\nv 0 0 0 # origin\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\n"
        "vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1\r\nf 1/1 2/2 3/3 4/4 # the face\r\n";
    const Mesh m = load_obj(write_obj("crlf.obj", text));
    EXPECT_EQ(m.triangle_count(), 2u);
    expect_sound(m);
    EXPECT_EQ(m.vertices[0].position, glm::vec3(0.0f));
}

// Every error names the file and has a one-line cause containing `expected`.
void expect_error(const std::string& path, const std::string& expected) {
    try {
        (void)load_obj(path);
        ADD_FAILURE() << path << ": no error thrown";
    } catch (const leanfade::Error& e) {
        EXPECT_EQ(e.file(), path);
        EXPECT_NE(e.cause().find(expected), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
}

TEST(LoadObjErrors, MissingFileAndDirectory) {
    expect_error((std::filesystem::path(LEANFADE_TEST_TMP) / "scene" / "nope.obj").string(),
                 "not found");
    const std::filesystem::path dir = std::filesystem::path(LEANFADE_TEST_TMP) / "scene" / "d.obj";
    std::filesystem::create_directories(dir);
    expect_error(dir.string(), "directory");
}

TEST(LoadObjErrors, NoTriangles) {
    expect_error(write_obj("empty.obj", ""), "no triangles");
    expect_error(write_obj("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\n"),
                 "no triangles");
    expect_error(write_obj("binary.obj", std::string("\x89PNG\r\n\x1a\n\0\0\0", 11)),
                 "no triangles");
}

TEST(LoadObjErrors, IndicesOutOfRange) {
    expect_error(write_obj("range_v.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "out of range");
    expect_error(write_obj("range_neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"),
                 "out of range");
    expect_error(
        write_obj("range_vn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n"),
        "out of range");
    expect_error(write_obj("range_vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n"),
                 "out of range");
    // A face may only use vertices defined before it.
    expect_error(write_obj("range_late.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n"),
                 "out of range");
}

TEST(LoadObjErrors, NonFiniteCoordinates) {
    expect_error(write_obj("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "non-finite");
    expect_error(write_obj("inf.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n"), "non-finite");
    expect_error(
        write_obj("nan_vn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 NaN 1\nf 1//1 2//1 3//1\n"),
        "non-finite");
}

TEST(LoadObjErrors, ParseFailures) {
    expect_error(write_obj("word.obj", "v 0 zero 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "line 1");
    expect_error(write_obj("short.obj", "v 0 0\n"), "needs at least 3");
    expect_error(write_obj("face_word.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 two 3\n"),
                 "malformed face vertex");
    expect_error(write_obj("face_zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
                 "malformed face vertex");
    expect_error(write_obj("face_two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"), "line 3");
}

TEST(LoadObj, ThroughMakeSceneMesh) {
    const std::string path = write_obj("Cube.OBJ", cube_with_normals_and_uvs());
    const Mesh m = make_scene_mesh(path);
    EXPECT_EQ(m.name, "Cube");
    EXPECT_EQ(m.triangle_count(), 12u);
}

}  // namespace
}  // namespace leanfade::scene
