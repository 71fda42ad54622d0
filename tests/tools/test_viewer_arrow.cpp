// The interactive viewer's force arrow scale (khz_viewer_input), headless: the frame pictures'
// linear scale for small forces, growing with the force, never longer than its bound, and the
// bound taken from what the camera sees.
#include <khz/render/camera.hpp>
#include <khz/viewer/force_arrow.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

namespace khz::viewer {
namespace {

/// 3 N drawn 0.2 m long on the linear scale, no arrow longer than 0.1 m.
constexpr ArrowScale scale{3.0, 0.2, 0.1};

TEST(ArrowScale, SmallForcesAreDrawnToTheFramePicturesScale) {
  for (const double force : {1e-9, 1e-6, 1e-4}) {
    EXPECT_NEAR(scale.length(force), force * 0.2 / 3.0, 1e-6 * force * 0.2 / 3.0) << force;
  }
  // At the reference force: max_length · tanh(reference_length / max_length) = 0.1 tanh(2).
  EXPECT_NEAR(scale.length(3.0), 0.1 * std::tanh(2.0), 1e-16);
}

TEST(ArrowScale, LengthGrowsWithTheForceAndStaysWithinItsBound) {
  double previous = 0.0;
  for (double force = 1e-6; force < 1e12; force *= 1.5) {
    const double length = scale.length(force);
    EXPECT_LE(length, scale.max_length) << force;
    EXPECT_GE(length, previous) << force;
    if (length < 0.999 * scale.max_length) {
      EXPECT_GT(length, previous) << force;
    }
    previous = length;
  }
  EXPECT_GT(scale.length(30.0), 0.999 * scale.max_length);  // ten times the reference: ~saturated
  EXPECT_EQ(scale.length(std::numeric_limits<double>::infinity()), scale.max_length);
  EXPECT_EQ(scale.length(0.0), 0.0);
  EXPECT_EQ(scale.length(-1.0), 0.0);
  EXPECT_EQ(scale.length(std::numeric_limits<double>::quiet_NaN()), 0.0);
}

TEST(ArrowScale, ArrowPointsAlongTheForce) {
  const Eigen::Vector3d force(0.0, 3.0, 4.0);  // 5 N
  const Eigen::Vector3d arrow = scale.arrow(force);
  EXPECT_NEAR(arrow.norm(), scale.length(5.0), 1e-16);
  EXPECT_LT((arrow.normalized() - force / 5.0).norm(), 1e-15);
  const Eigen::Vector3d huge = scale.arrow(Eigen::Vector3d(-1e9, 0.0, 0.0));
  EXPECT_LE(huge.norm(), scale.max_length);
  EXPECT_LT(huge.x(), 0.0);
  EXPECT_EQ(scale.arrow(Eigen::Vector3d::Zero()), Eigen::Vector3d::Zero());
  EXPECT_EQ(scale.arrow(Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 1.0, 0.0)),
            Eigen::Vector3d::Zero());
  EXPECT_EQ(scale.arrow(Eigen::Vector3d(std::numeric_limits<double>::infinity(), 0.0, 0.0)),
            Eigen::Vector3d::Zero());
}

TEST(ArrowScale, ViewHalfExtentIsTheSmallerHalfSideAtThePointsDepth) {
  // 200 × 100 pixels, 60° vertically, from (0, 0, 2) towards the origin: the height is the
  // smaller side, 2 tan(30°) either side of the axis at depth 2.
  const render::Camera camera({0.0, 0.0, 2.0}, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(),
                              std::numbers::pi / 3.0, 200, 100);
  EXPECT_NEAR(view_half_extent(camera, Eigen::Vector3d::Zero()),
              2.0 * std::tan(std::numbers::pi / 6.0), 1e-15);
  EXPECT_NEAR(view_half_extent(camera, {0.3, -0.2, 1.0}), std::tan(std::numbers::pi / 6.0), 1e-15);
  EXPECT_EQ(view_half_extent(camera, {0.0, 0.0, 3.0}), 0.0);  // behind the eye
  // An arrow bounded by the extent, drawn from the view's centre, ends inside the image.
  const ArrowScale bounded{1.0, 1.0, 0.9 * view_half_extent(camera, Eigen::Vector3d::Zero())};
  for (const Eigen::Vector3d& force :
       {Eigen::Vector3d(1e6, 0.0, 0.0), Eigen::Vector3d(0.0, -1e6, 0.0),
        Eigen::Vector3d(1e6, 1e6, 0.0)}) {
    const std::optional<render::ScreenPoint> tip = camera.project(bounded.arrow(force));
    ASSERT_TRUE(tip.has_value());
    EXPECT_GE(tip->pixel.x(), 0.0);
    EXPECT_LT(tip->pixel.x(), 200.0);
    EXPECT_GE(tip->pixel.y(), 0.0);
    EXPECT_LT(tip->pixel.y(), 100.0);
  }
}

TEST(ArrowScale, RoomInViewIsHowFarTheArrowMayReachInsideTheMargin) {
  // As above: from (0, 0, 2) towards the origin, 200 × 100 pixels; 10 pixels of margin.
  const render::Camera camera({0.0, 0.0, 2.0}, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(),
                              std::numbers::pi / 3.0, 200, 100);
  const double f = camera.focal_length();
  const Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  // Right: x = 100 + f t / 2 reaches 190 at t = 180 / f; up: y = 50 − f t / 2 reaches 10.
  EXPECT_NEAR(room_in_view(camera, centre, Eigen::Vector3d::UnitX(), 10.0), 180.0 / f, 1e-15);
  EXPECT_NEAR(room_in_view(camera, centre, Eigen::Vector3d::UnitY(), 10.0), 80.0 / f, 1e-15);
  // Towards the eye, the near distance stops it; straight away from it, nothing does.
  EXPECT_NEAR(room_in_view(camera, centre, Eigen::Vector3d::UnitZ(), 10.0),
              2.0 - camera.near_distance(), 1e-15);
  EXPECT_EQ(room_in_view(camera, centre, -Eigen::Vector3d::UnitZ(), 10.0),
            std::numeric_limits<double>::infinity());
  // A start in the margin or out of view has no room.
  const Eigen::Vector3d in_margin(95.0 * 2.0 / f, 0.0, 0.0);  // pixel x = 195
  EXPECT_EQ(room_in_view(camera, in_margin, -Eigen::Vector3d::UnitX(), 10.0), 0.0);
  EXPECT_EQ(room_in_view(camera, {0.0, 0.0, 3.0}, Eigen::Vector3d::UnitX(), 10.0), 0.0);

  // The arrow of any force, capped by the room from its start, ends inside the margin.
  const Eigen::Vector3d start(0.3, -0.2, 0.4);
  for (const Eigen::Vector3d& force :
       {Eigen::Vector3d(1e3, 0.0, 0.0), Eigen::Vector3d(0.0, -1e3, 0.0),
        Eigen::Vector3d(-1e3, 2e3, 0.5e3), Eigen::Vector3d(0.2, 0.1, 1e3),
        Eigen::Vector3d(1e3, 1e3, -1e3)}) {
    const double room = room_in_view(camera, start, force.normalized(), 10.0);
    ASSERT_GT(room, 0.0);
    const ArrowScale capped{1.0, 1.0, std::min(room, 5.0)};
    const Eigen::Vector3d tip = start + capped.arrow(force);
    EXPECT_GT(camera.to_view(tip).z(), camera.near_distance());
    const Eigen::Vector2d pixel = camera.view_to_pixel(camera.to_view(tip));
    EXPECT_GE(pixel.x(), 10.0 - 1e-9) << force.transpose();
    EXPECT_LE(pixel.x(), 190.0 + 1e-9) << force.transpose();
    EXPECT_GE(pixel.y(), 10.0 - 1e-9) << force.transpose();
    EXPECT_LE(pixel.y(), 90.0 + 1e-9) << force.transpose();
  }
}

}  // namespace
}  // namespace khz::viewer
