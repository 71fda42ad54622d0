// The interactive viewer's mouse as a manipulandum (khz_viewer_input), headless: the cursor's
// point on the plane facing the camera, drags and scrolls, MouseDevice's read/write semantics,
// its workspace mapping, and a scene runtime closed through a MouseDevice pressing into a wall.
#include "scene_fixtures.hpp"

#include <khz/haptic/device/safe_device.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/scene_runtime.hpp>
#include <khz/viewer/cursor_drag.hpp>
#include <khz/viewer/cursor_plane.hpp>
#include <khz/viewer/mouse_device.hpp>
#include <khz/viewer/mouse_placement.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace khz::viewer {
namespace {

constexpr double fov = std::numbers::pi / 3.0;

/// 200 × 100 pixels looking down −z from (0, 0, 2) at the origin, y up: right is +x.
render::Camera axis_camera() {
  return render::Camera({0.0, 0.0, 2.0}, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), fov,
                        200, 100);
}

/// An oblique camera, as the viewer frames scenes.
render::Camera oblique_camera() {
  return render::Camera({1.0, 0.8, 1.6}, {0.1, 0.2, 0.3}, Eigen::Vector3d::UnitY(), fov, 320, 240);
}

TEST(CursorPlane, CentrePixelMapsToThePlanesPointOnTheViewingAxis) {
  const render::Camera camera = axis_camera();
  const Eigen::Vector2d centre(100.0, 50.0);
  EXPECT_LT((cursor_on_plane(camera, centre, camera.target()) - camera.target()).norm(), 1e-15);
  // Any point of the plane z = −0.5 names the same plane: the axis meets it at (0, 0, −0.5).
  const Eigen::Vector3d hit = cursor_on_plane(camera, centre, {0.3, -0.2, -0.5});
  EXPECT_LT((hit - Eigen::Vector3d(0.0, 0.0, -0.5)).norm(), 1e-15);
}

TEST(CursorPlane, PixelOffsetMapsToTheWorldOffsetAtThePlanesDepth) {
  const render::Camera camera = axis_camera();
  const double f = 50.0 / std::tan(0.5 * fov);  // focal length (pixels): height / (2 tan(fov/2))
  EXPECT_NEAR(camera.focal_length(), f, 1e-12);
  // 10 pixels right and 5 up at depth 2: (10, 5) · 2 / f in x and y.
  const Eigen::Vector3d hit = cursor_on_plane(camera, {110.0, 45.0}, Eigen::Vector3d::Zero());
  EXPECT_NEAR(hit.x(), 20.0 / f, 1e-15);
  EXPECT_NEAR(hit.y(), 10.0 / f, 1e-15);
  EXPECT_NEAR(hit.z(), 0.0, 1e-15);
}

TEST(CursorPlane, PointLiesOnThePlaneAndProjectsBackUnderTheCursor) {
  const render::Camera camera = oblique_camera();
  const Eigen::Vector3d plane_point(0.2, 0.1, 0.4);
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(17.5, 200.25), Eigen::Vector2d(319.0, 3.0),
        Eigen::Vector2d(-40.0, 500.0)}) {
    const Eigen::Vector3d hit = cursor_on_plane(camera, pixel, plane_point);
    EXPECT_NEAR((hit - plane_point).dot(camera.forward()), 0.0, 1e-14);
    const std::optional<render::ScreenPoint> projected = camera.project(hit);
    ASSERT_TRUE(projected.has_value());
    EXPECT_LT((projected->pixel - pixel).norm(), 1e-9) << pixel.transpose();
  }
}

TEST(CursorDrag, FollowsTheCursorWhileHeldScrollsAlongTheViewAndStaysInItsBox) {
  const render::Camera camera = axis_camera();
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d::Constant(-1.0), Eigen::Vector3d::Constant(1.0));
  CursorDrag drag({0.1, 0.2, 0.0}, bounds, 0.05);
  const double metres_per_pixel = 2.0 / camera.focal_length();

  drag.move(camera, {150.0, 20.0});  // not held: nothing happens
  EXPECT_EQ(drag.target(), Eigen::Vector3d(0.1, 0.2, 0.0));
  drag.press(camera, {150.0, 20.0});  // pressing away from the target does not move it
  EXPECT_TRUE(drag.dragging());
  EXPECT_EQ(drag.target(), Eigen::Vector3d(0.1, 0.2, 0.0));
  drag.move(camera, {160.0, 30.0});  // 10 right, 10 down
  EXPECT_LT((drag.target() -
             Eigen::Vector3d(0.1 + 10.0 * metres_per_pixel, 0.2 - 10.0 * metres_per_pixel, 0.0))
                .norm(),
            1e-14);
  drag.release();
  const Eigen::Vector3d released = drag.target();
  drag.move(camera, {0.0, 0.0});
  EXPECT_EQ(drag.target(), released);

  drag.scroll(camera, 2.0);  // two notches away from the eye: −z
  EXPECT_LT((drag.target() - (released + Eigen::Vector3d(0.0, 0.0, -0.1))).norm(), 1e-15);
  drag.scroll(camera, -100.0);  // far towards the eye: stopped by the box at z = 1
  EXPECT_EQ(drag.target().z(), 1.0);
  drag.press(camera, {100.0, 50.0});
  drag.move(camera, {100.0 + 1e4, 50.0});  // far right: stopped at x = 1
  EXPECT_EQ(drag.target().x(), 1.0);
}

TEST(MouseDevice, CapabilitiesArePositionInNoOutputAndAWorkspaceBox) {
  const MouseDevice mouse(500.0, 0.3);
  const haptic::DeviceCapabilities& capabilities = mouse.capabilities();
  EXPECT_NO_THROW(capabilities.validate());
  EXPECT_EQ(capabilities.input_dof, 3);
  EXPECT_EQ(capabilities.output_dof, 0);
  EXPECT_EQ(capabilities.nominal_rate, 500.0);
  EXPECT_EQ(capabilities.workspace_min, Eigen::Vector3d::Constant(-0.3));
  EXPECT_EQ(capabilities.workspace_max, Eigen::Vector3d::Constant(0.3));
  EXPECT_THROW(MouseDevice(0.0), haptic::Error);
  EXPECT_THROW(MouseDevice(1000.0, -1.0), haptic::Error);
}

TEST(MouseDevice, ReadReturnsTheLatestPositionAndWriteKeepsTheWrench) {
  MouseDevice mouse(1000.0, 0.3);
  haptic::DeviceState state;
  state.valid = true;
  EXPECT_FALSE(mouse.read(state));  // closed
  EXPECT_FALSE(state.valid);
  EXPECT_FALSE(mouse.write(haptic::Wrench{}));

  mouse.open();
  ASSERT_TRUE(mouse.read(state));  // before any set_position(): the origin
  EXPECT_TRUE(state.valid);
  EXPECT_EQ(state.pose.position, Eigen::Vector3d::Zero());
  EXPECT_TRUE(state.pose.orientation.isApprox(Eigen::Quaterniond::Identity()));
  EXPECT_FALSE(state.has_linear_velocity);
  EXPECT_FALSE(state.has_angular_velocity);
  const double first_time = state.time;

  mouse.set_position({0.01, 0.02, 0.03});
  mouse.set_position({0.04, -0.05, 0.06});  // only the newest counts
  ASSERT_TRUE(mouse.read(state));
  EXPECT_EQ(state.pose.position, Eigen::Vector3d(0.04, -0.05, 0.06));
  EXPECT_GE(state.time, first_time);
  ASSERT_TRUE(mouse.read(state));  // nothing new: the same position again
  EXPECT_EQ(state.pose.position, Eigen::Vector3d(0.04, -0.05, 0.06));

  mouse.set_position({1.0, -0.1, -2.0});  // clamped to the box
  mouse.read(state);
  EXPECT_EQ(state.pose.position, Eigen::Vector3d(0.3, -0.1, -0.3));
  mouse.set_position({std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0});  // ignored
  mouse.read(state);
  EXPECT_EQ(state.pose.position, Eigen::Vector3d(0.3, -0.1, -0.3));

  EXPECT_EQ(mouse.last_wrench().force, Eigen::Vector3d::Zero());
  haptic::Wrench wrench;
  wrench.force = {1.0, 2.0, 3.0};
  wrench.torque = {0.1, 0.2, 0.3};
  EXPECT_TRUE(mouse.write(wrench));
  EXPECT_EQ(mouse.last_wrench().force, wrench.force);
  EXPECT_EQ(mouse.last_wrench().torque, wrench.torque);
  mouse.close();
  EXPECT_FALSE(mouse.read(state));
}

// Through the safety layer with mouse_mapping(): device_position() of a world point reads back
// as that world point, turned like the grasp frame; the mouse gets no force.
TEST(MousePlacement, DevicePositionInvertsTheMapping) {
  haptic::Pose grasp;
  grasp.position = {0.1, -0.2, 0.3};
  grasp.orientation =
      Eigen::Quaterniond(Eigen::AngleAxisd(-0.5 * std::numbers::pi, Eigen::Vector3d::UnitX()));
  MouseDevice mouse;
  haptic::SafeDevice safe(mouse, {}, mouse_mapping(grasp));
  safe.open();
  const Eigen::Vector3d world(0.12, -0.15, 0.33);
  mouse.set_position(device_position(safe.mapping(), world));
  haptic::DeviceState state;
  ASSERT_TRUE(safe.read(state));
  EXPECT_LT((state.pose.position - world).norm(), 1e-15);
  EXPECT_TRUE(state.pose.orientation.isApprox(grasp.orientation, 1e-15));
  haptic::Wrench wrench;
  wrench.force = {0.0, 3.0, 0.0};
  EXPECT_TRUE(safe.write(wrench));
  EXPECT_EQ(mouse.last_wrench().force, Eigen::Vector3d::Zero());  // no force output
}

// A 4 cm cube "tool" 1 cm above a 10 cm cube "wall" (top face at y = 0.05), moved by a
// MouseDevice into the wall: the coupling pulls it into contact and the wall pushes back.
TEST(MouseDevice, DrivesASceneRuntimeIntoContact) {
  const nlohmann::json json = scene::test_scenes::cube_above_wall_scene();
  const scene::SceneDescription description =
      scene::parse_scene(json.dump(), "mouse scene", scene::test_scenes::read_options());
  scene::ProductCache cache(test::scratch_file("cache.probe").parent_path() / "cache");
  const scene::PreparedScene prepared = scene::prepare_scene(description, cache);

  MouseDevice mouse(description.loop.rate_hz);
  haptic::Device* const devices[] = {&mouse};
  scene::SceneRuntime runtime(prepared, devices);
  EXPECT_EQ(&runtime.raw_device(), &mouse);
  const haptic::Pose start = runtime.world().coupling(0).simulation_pose();
  EXPECT_LT((start.position - Eigen::Vector3d(0.0, 0.08, 0.0)).norm(), 1e-15);
  runtime.device().set_mapping(mouse_mapping(start));
  const Eigen::Vector3d pressed(0.0, 0.067, 0.0);  // the tool's bottom 3 mm below the top face
  mouse.set_position(device_position(runtime.device().mapping(), pressed));

  runtime.open_devices();
  const double period = 1.0 / description.loop.rate_hz;
  haptic::CycleRecord last;
  for (int i = 0; i < 300; ++i) {
    const double now = i * period;
    last = runtime.world().cycle(now, now + period, [now] { return now; }).front();
  }
  runtime.close_devices();
  EXPECT_TRUE(last.device_valid && last.contact_valid && last.coupling_valid);
  EXPECT_LT((last.manipulandum.position - pressed).norm(), 1e-15);
  EXPECT_GT(last.contact.statistics.points_in_contact, 0);
  EXPECT_TRUE(last.contact.force.allFinite());
  EXPECT_GT(last.contact.force.y(), 0.0);          // pushed up, out of the wall
  EXPECT_LT(last.simulation.position.y(), 0.071);  // held near the face by the contact
  EXPECT_GT(last.simulation.position.y(), pressed.y());
}

}  // namespace
}  // namespace khz::viewer
