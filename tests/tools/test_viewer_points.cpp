// The interactive viewer's contact points (khz_viewer_input), headless: SnapshotPoints classifies
// each pair's points from a SceneSnapshot exactly as run::capture_frame() does from the live
// scene, for rigid objects and for reduced ones (a deformable pointshell against a deformed
// field), and a snapshot once taken keeps giving the same points however the scene runs on.
#include "scene_fixtures.hpp"

#include <khz/run/frame_content.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/scene_runtime.hpp>
#include <khz/viewer/mouse_device.hpp>
#include <khz/viewer/mouse_placement.hpp>
#include <khz/viewer/scene_snapshot.hpp>
#include <khz/viewer/snapshot_points.hpp>

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace khz::viewer {
namespace {

/// A scene run by a MouseDevice on hand 0, in simulated time.
class MouseScene {
 public:
  MouseScene(const nlohmann::json& json, const char* cache)
      : m_description(scene::parse_scene(json.dump(), "viewer points scene",
                                         scene::test_scenes::read_options())),
        m_cache(test::scratch_directory(cache)),
        m_prepared(scene::prepare_scene(m_description, m_cache)),
        m_mouse(m_description.loop.rate_hz) {
    haptic::Device* const devices[] = {&m_mouse};
    m_runtime = std::make_unique<scene::SceneRuntime>(m_prepared, devices);
    m_runtime->device().set_mapping(
        mouse_mapping(m_runtime->world().coupling(0).simulation_pose()));
    m_runtime->open_devices();
  }
  ~MouseScene() { m_runtime->close_devices(); }

  scene::SceneRuntime& runtime() { return *m_runtime; }

  /// Puts the mouse at `target` (m, world) and runs `cycles` cycles.
  void hold_at(const Eigen::Vector3d& target, int cycles) {
    m_mouse.set_position(device_position(m_runtime->device().mapping(), target));
    const double period = 1.0 / m_description.loop.rate_hz;
    for (int i = 0; i < cycles; ++i, ++m_cycle) {
      const double now = m_cycle * period;
      m_runtime->world().cycle(now, now + period, [now] { return now; });
    }
  }

 private:
  scene::SceneDescription m_description;
  scene::ProductCache m_cache;
  scene::PreparedScene m_prepared;
  MouseDevice m_mouse;
  std::unique_ptr<scene::SceneRuntime> m_runtime;
  long m_cycle = 0;
};

void expect_same(const std::vector<run::PointPicture>& actual,
                 const std::vector<run::PointPicture>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t k = 0; k < actual.size(); ++k) {
    SCOPED_TRACE(k);
    ASSERT_EQ(actual[k].positions.rows(), expected[k].positions.rows());
    EXPECT_TRUE((actual[k].positions.array() == expected[k].positions.array()).all());
    EXPECT_EQ(actual[k].states, expected[k].states);
  }
}

std::int64_t in_contact(const std::vector<run::PointPicture>& pictures) {
  std::int64_t count = 0;
  for (const run::PointPicture& picture : pictures)
    count += picture.count(run::PointState::in_contact);
  return count;
}

// The same press with friction, the hand then sliding the cube along the wall: the snapshot
// lists the points that slid, and the viewer colours them as the frame pictures do.
TEST(SnapshotPoints, SlidingPointsAsTheFramePictures) {
  nlohmann::json json = scene::test_scenes::cube_above_wall_scene();
  json["contact"]["friction"] = {{"static", 0.5}, {"kinetic", 0.4}};
  MouseScene scene(json, "viewer-points-sliding");
  const SnapshotLayout layout(scene.runtime());
  SnapshotPoints points(scene.runtime(), layout);
  scene.hold_at({0.0, 0.067, 0.0}, 300);
  std::int64_t slid = 0;
  for (int step = 1; step <= 20 && slid == 0; ++step) {
    scene.hold_at({1e-3 * step, 0.067, 0.0}, 10);
    slid = scene.runtime().world().pair_result(0).statistics.points_sliding;
  }
  ASSERT_GT(slid, 0) << "the hand slid the cube along the wall";
  auto sliding = std::make_unique<SceneSnapshot>();
  layout.capture(scene.runtime(), *sliding);
  EXPECT_EQ(sliding->sliding_counts[0], slid);
  const std::vector<run::PointPicture> pictures = points.classify(*sliding);
  expect_same(pictures, run::capture_frame(scene.runtime()).points);
  EXPECT_EQ(pictures[0].count(run::PointState::sliding), slid);
}

// A rigid 4 cm cube (500 random points) pressed 3 mm into a rigid 10 cm cube, then lifted off.
TEST(SnapshotPoints, RigidObjectsAsTheFramePictures) {
  const nlohmann::json json = scene::test_scenes::cube_above_wall_scene();
  MouseScene scene(json, "viewer-points-rigid");
  const SnapshotLayout layout(scene.runtime());
  SnapshotPoints points(scene.runtime(), layout);
  ASSERT_EQ(points.picture_count(), 1);

  scene.hold_at({0.0, 0.067, 0.0}, 300);
  auto pressed = std::make_unique<SceneSnapshot>();
  layout.capture(scene.runtime(), *pressed);
  EXPECT_EQ(pressed->deepest_levels[0],
            scene.runtime().world().pair_result(0).statistics.deepest_level);
  const std::vector<run::PointPicture> touching = points.classify(*pressed);
  expect_same(touching, run::capture_frame(scene.runtime()).points);
  EXPECT_GT(in_contact(touching), 0);
  EXPECT_GT(touching[0].count(run::PointState::traversed), 0);

  scene.hold_at({0.0, 0.1, 0.0}, 300);  // lifted 2 cm clear of the wall
  auto lifted = std::make_unique<SceneSnapshot>();
  layout.capture(scene.runtime(), *lifted);
  const std::vector<run::PointPicture> apart = points.classify(*lifted);
  expect_same(apart, run::capture_frame(scene.runtime()).points);
  EXPECT_EQ(in_contact(apart), 0);
  // The old snapshot still shows the contact: nothing is read from the running scene.
  expect_same(points.classify(*pressed), touching);
}

TEST(SnapshotPoints, ReducedObjectsUseTheSnapshotsCoordinatesAndTheirOwnDeformedField) {
  nlohmann::json json = scene::test_scenes::reduced_pair_scene();
  json["objects"][0]["pose"] = {{"position", {0.0, 0.1, 0.0}}};
  MouseScene scene(json, "viewer-points-reduced");
  const SnapshotLayout layout(scene.runtime());
  SnapshotPoints points(scene.runtime(), layout);
  ASSERT_EQ(points.picture_count(), 1);

  scene.hold_at({0.0, 0.087, 0.0}, 300);                  // the tool's bottom 3 mm into the wall
  ASSERT_GT(scene.runtime().coordinates(0).norm(), 0.0);  // both deformed
  ASSERT_GT(scene.runtime().coordinates(1).norm(), 0.0);
  auto pressed = std::make_unique<SceneSnapshot>();
  layout.capture(scene.runtime(), *pressed);
  EXPECT_EQ(layout.coordinates(*pressed, 1), scene.runtime().coordinates(1));
  const std::vector<run::PointPicture> touching = points.classify(*pressed);
  expect_same(touching, run::capture_frame(scene.runtime()).points);
  EXPECT_GT(in_contact(touching), 0);

  scene.hold_at({0.0, 0.12, 0.0}, 200);  // lifted: both spring back
  ASSERT_NE(scene.runtime().coordinates(1), layout.coordinates(*pressed, 1));
  auto lifted = std::make_unique<SceneSnapshot>();
  layout.capture(scene.runtime(), *lifted);
  expect_same(points.classify(*lifted), run::capture_frame(scene.runtime()).points);
  // Back to the pressed snapshot: its own field state takes that q again.
  expect_same(points.classify(*pressed), touching);
}

}  // namespace
}  // namespace khz::viewer
