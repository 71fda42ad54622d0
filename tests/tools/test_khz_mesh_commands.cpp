// khz repair run end to end on CGAL's demo meshes: what it prints is what it did.

#include "khz_command.hpp"

#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <string>

namespace khz::test {
namespace {

/// `khz repair [options] elephant-with-holes.off output`.
KhzRun repair_elephant(const std::string& options, const std::filesystem::path& output) {
  return khz("repair " + options + " \"" + cgal_mesh("elephant-with-holes.off").string() + "\" \"" +
             output.string() + "\"");
}

TEST(KhzRepair, SaysWhenOrientingCopiesTheVerticesItWelded) {
  const std::filesystem::path output = scratch_file("elephant-repaired.off");
  const KhzRun run = repair_elephant("--weld 1e-6", output);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const reduced::MeshReport report = reduced::analyze_mesh(reduced::read_triangle_mesh(output));
  ASSERT_GT(report.num_duplicate_vertices, 0);
  EXPECT_TRUE(has_line_with(
      run, {"orienting copied " + std::to_string(report.num_duplicate_vertices) + " vertices",
            "--keep-orientation"}));
}

TEST(KhzRepair, KeepOrientationWeldsEveryDuplicate) {
  const std::filesystem::path output = scratch_file("elephant-welded.off");
  const KhzRun run = repair_elephant("--weld 1e-6 --keep-orientation", output);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(reduced::analyze_mesh(reduced::read_triangle_mesh(output)).num_duplicate_vertices, 0);
  EXPECT_EQ(run.output.find("orienting copied"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace khz::test
