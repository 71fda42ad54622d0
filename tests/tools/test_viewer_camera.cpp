// The interactive viewer's orbit camera (khz_viewer_input), headless: it starts where the frame
// pictures' framing puts the eye, orbiting turns the view about the scene's centre at a fixed
// distance, zooming changes only the distance, both stay within their ranges, and reset()
// restores the start view.
#include <khz/reduced/errors.hpp>
#include <khz/run/frame_renderer.hpp>
#include <khz/run/scene_framing.hpp>
#include <khz/viewer/orbit_camera.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>

namespace khz::viewer {
namespace {

run::SceneFraming framing() {
  run::SceneFraming f;
  f.centre = {0.1, -0.2, 0.3};
  f.radius = 0.5;
  return f;
}

const Eigen::Vector3d view_direction = run::FrameOptions().view_direction;  // (1, 0.8, 1.6)
const Eigen::Vector3d up = Eigen::Vector3d::UnitY();

double distance(const render::Camera& camera) { return (camera.eye() - camera.target()).norm(); }

TEST(OrbitCamera, StartsAtTheFramePicturesViewOfTheScene) {
  const OrbitCamera orbit(framing(), view_direction, up);
  for (const auto& [width, height] : {std::pair{800, 600}, std::pair{300, 900}}) {
    const render::Camera camera = orbit.camera(width, height);
    const render::Camera expected = framing().camera(view_direction, up, width, height);
    EXPECT_EQ(camera.target(), framing().centre);
    EXPECT_LT((camera.eye() - expected.eye()).norm(), 1e-12) << width << "x" << height;
    EXPECT_EQ(camera.vertical_fov(), expected.vertical_fov());
    EXPECT_EQ(camera.width(), width);
    EXPECT_EQ(camera.height(), height);
  }
  EXPECT_EQ(orbit.zoom_factor(), 1.0);
  EXPECT_EQ(orbit.azimuth(), 0.0);
  EXPECT_NEAR(orbit.elevation(), std::asin(0.8 / view_direction.norm()), 1e-15);
}

TEST(OrbitCamera, OrbitingTurnsAboutTheCentreAndKeepsTheDistance) {
  OrbitCamera orbit(framing(), view_direction, up, 0.01);
  const render::Camera start = orbit.camera(800, 600);

  orbit.orbit({100.0, 0.0});  // 100 pixels right: the eye goes 1 rad to the left, level
  const render::Camera turned = orbit.camera(800, 600);
  EXPECT_EQ(turned.target(), framing().centre);
  EXPECT_NEAR(distance(turned), distance(start), 1e-12 * distance(start));
  EXPECT_NEAR(orbit.azimuth(), -1.0, 1e-15);
  EXPECT_LT((turned.eye() - start.eye()).dot(start.right()), -0.1);
  EXPECT_NEAR(turned.eye().y(), start.eye().y(), 1e-12);  // about the up axis: same height
  // The angle between the two views' horizontal directions is the azimuth's change.
  const auto horizontal = [](const render::Camera& c) {
    return Eigen::Vector3d(c.forward().x(), 0.0, c.forward().z()).normalized();
  };
  EXPECT_NEAR(std::acos(horizontal(turned).dot(horizontal(start))), 1.0, 1e-12);

  const double elevation = orbit.elevation();
  orbit.orbit({0.0, 20.0});  // 20 pixels down: the eye rises 0.2 rad
  const render::Camera raised = orbit.camera(800, 600);
  EXPECT_NEAR(orbit.elevation(), elevation + 0.2, 1e-15);
  EXPECT_GT(raised.eye().y(), turned.eye().y());
  EXPECT_NEAR(distance(raised), distance(start), 1e-12 * distance(start));

  orbit.orbit({std::numeric_limits<double>::quiet_NaN(), 1.0});  // ignored
  EXPECT_NEAR(orbit.elevation(), elevation + 0.2, 1e-15);
}

TEST(OrbitCamera, ElevationStopsShortOfThePoles) {
  OrbitCamera orbit(framing(), view_direction, up);
  orbit.orbit({0.0, 1e6});  // far down: over the top would look along up
  EXPECT_EQ(orbit.elevation(), OrbitCamera::max_elevation);
  const render::Camera top = orbit.camera(640, 480);  // render::Camera accepts it
  EXPECT_NEAR(-top.forward().dot(up), std::sin(OrbitCamera::max_elevation), 1e-12);
  orbit.orbit({0.0, -1e7});
  EXPECT_EQ(orbit.elevation(), -OrbitCamera::max_elevation);
  EXPECT_NO_THROW(orbit.camera(640, 480));
}

TEST(OrbitCamera, ZoomScalesOnlyTheDistanceWithinItsRange) {
  OrbitCamera orbit(framing(), view_direction, up);
  const render::Camera start = orbit.camera(800, 600);
  orbit.zoom(1.0);  // one notch nearer
  const render::Camera nearer = orbit.camera(800, 600);
  EXPECT_NEAR(distance(nearer), distance(start) / OrbitCamera::zoom_step, 1e-12);
  EXPECT_LT((nearer.forward() - start.forward()).norm(), 1e-12);
  EXPECT_EQ(nearer.target(), start.target());
  orbit.zoom(-3.0);  // three notches farther: two beyond the start
  EXPECT_NEAR(distance(orbit.camera(800, 600)),
              distance(start) * OrbitCamera::zoom_step * OrbitCamera::zoom_step, 1e-12);

  orbit.zoom(-1000.0);
  EXPECT_EQ(orbit.zoom_factor(), OrbitCamera::max_zoom);
  EXPECT_NEAR(distance(orbit.camera(800, 600)), OrbitCamera::max_zoom * distance(start), 1e-9);
  orbit.zoom(1000.0);
  EXPECT_EQ(orbit.zoom_factor(), 1.0 / OrbitCamera::max_zoom);
  orbit.zoom(std::numeric_limits<double>::infinity());  // ignored
  EXPECT_EQ(orbit.zoom_factor(), 1.0 / OrbitCamera::max_zoom);
}

TEST(OrbitCamera, ResetRestoresTheStartView) {
  OrbitCamera orbit(framing(), view_direction, up);
  const render::Camera start = orbit.camera(800, 600);
  orbit.orbit({-250.0, 75.0});
  orbit.zoom(4.0);
  ASSERT_GT((orbit.camera(800, 600).eye() - start.eye()).norm(), 0.1);
  orbit.reset();
  const render::Camera reset = orbit.camera(800, 600);
  EXPECT_EQ(reset.eye(), start.eye());
  EXPECT_EQ(reset.target(), start.target());
  EXPECT_EQ(orbit.zoom_factor(), 1.0);
}

TEST(OrbitCamera, RefusesDirectionsWithoutAnAzimuth) {
  EXPECT_THROW(OrbitCamera(framing(), up, up), reduced::Error);
  EXPECT_THROW(OrbitCamera(framing(), -2.0 * up, up), reduced::Error);
  EXPECT_THROW(OrbitCamera(framing(), Eigen::Vector3d::Zero(), up), reduced::Error);
  EXPECT_THROW(OrbitCamera(framing(), view_direction, Eigen::Vector3d::Zero()), reduced::Error);
  EXPECT_THROW(OrbitCamera(framing(), view_direction, up, 0.0), reduced::Error);
}

}  // namespace
}  // namespace khz::viewer
