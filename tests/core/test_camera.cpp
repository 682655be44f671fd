// The camera's settings, one rule each (leanfade/core/detail/camera.hpp): the renderer, presets, eval
// and every command line check distances and the field of view through these.
#include <gtest/gtest.h>

#include <limits>

#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/error.hpp"

namespace leanfade {
namespace {

TEST(Camera, DistancesAreInOneToTenThousandRadii) {
    for (double d : {1.0001, 2.0, 64.0, double(kMaxCameraDistance)})
        EXPECT_NO_THROW(check_camera_distance(d, "distances")) << d;
    for (double d : {1.0, 0.5, -3.0, 10000.5, 1e30, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()})
        EXPECT_THROW(check_camera_distance(d, "distances"), Error) << d;
    try {
        check_camera_distance(0.5, "--distances", "0.50");
        FAIL() << "0.5 radii must be refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "--distances");
        EXPECT_NE(e.cause().find("got 0.50"), std::string::npos) << e.what();  // as given
    }
}

TEST(Camera, FieldOfViewIsOpenOneToOneHundredSeventyDegrees) {
    for (float f : {1.5f, 34.0f, 169.9f}) EXPECT_NO_THROW(check_field_of_view(f, "fov")) << f;
    for (float f : {1.0f, 170.0f, 0.0f, -10.0f, std::numeric_limits<float>::quiet_NaN()})
        EXPECT_THROW(check_field_of_view(f, "fov"), Error) << f;
}

}  // namespace
}  // namespace leanfade
