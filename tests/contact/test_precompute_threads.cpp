// libcontact's precomputations keep to reduced::worker_threads() (issue 23 item 4): a signed
// distance field, a repulsion pointshell (seeding, neighbour lists, relaxation, normals) and its
// point tree, counted from outside as test_reduced_worker_threads does, on the second run under
// each setting.

#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/pointshell/repulsion_pointshell.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/test/generated_meshes.hpp>
#include <khz/test/threads_that_ran.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace khz::contact {
namespace {

void field_pointshell_and_tree() {
  static const TriangleMesh sphere = test::uv_sphere(48, 24);
  DistanceFieldOptions field;
  field.cells = 64;
  RepulsionOptions shell;
  shell.first_level_points = 64;
  shell.levels = 4;
  shell.tolerance = 2e-3;
  const PointTree tree(repulsion_pointshell(sphere, field, shell));
  ASSERT_EQ(tree.num_points(), 64 * (1 + 4 + 16 + 64));
}

TEST(PrecomputeThreads, OneThreadMeansNoOtherThreadRuns) {
  const reduced::ScopedWorkerThreads one(1);
  const std::vector<std::string> ran =
      test::other_threads_in_a_second_run(field_pointshell_and_tree);
  EXPECT_TRUE(ran.empty()) << test::listed(ran);
}

TEST(PrecomputeThreads, TwoThreadsMeanOneOther) {
  if (test::usable_cores() < 2) GTEST_SKIP() << "one core: nothing to share";
  const reduced::ScopedWorkerThreads two(2);
  const std::vector<std::string> ran =
      test::other_threads_in_a_second_run(field_pointshell_and_tree);
  EXPECT_EQ(ran.size(), 1U) << test::listed(ran);
}

}  // namespace
}  // namespace khz::contact
