#include <khz/contact/common.hpp>
#include <khz/contact/io/point_tree_file.hpp>
#include <khz/contact/io/pointshell_file.hpp>
#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace khz::contact {
namespace {

void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

Pointshell nested_sphere(Eigen::Index count, Eigen::Index first_level) {
  NestedLevelOptions options;
  options.schedule = LevelSchedule::quadrupling(first_level);
  return nested_pointshell(random_pointshell(test::uv_sphere(16, 9), count, 7), options);
}

/// Random modes (any modes bound the same way), r per point, with a few awkward entries.
std::vector<double> random_modes(Eigen::Index points, Eigen::Index r, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> gauss(0.0, 0.2);
  std::vector<double> modes(static_cast<std::size_t>(3 * r * points));
  for (double& x : modes) x = gauss(random);
  modes[0] = -0.0;
  modes[1] = std::numeric_limits<double>::denorm_min();
  return modes;
}

DeformablePointTree make_tree(Eigen::Index count, Eigen::Index first_level, Eigen::Index r) {
  PointTree tree(nested_sphere(count, first_level));
  const Eigen::Index n = tree.num_points();
  return DeformablePointTree(std::move(tree), r, random_modes(n, r, 1), random_modes(n, r, 2));
}

const DeformablePointTree& large_tree() {
  static const DeformablePointTree tree = make_tree(1500, 6, 5);
  return tree;
}

void expect_same_point_tree(const PointTree& a, const PointTree& b) {
  ASSERT_EQ(a.num_levels(), b.num_levels());
  for (int level = 0; level <= a.num_levels(); ++level) {
    EXPECT_EQ(a.level_begin(level), b.level_begin(level));
  }
  ASSERT_EQ(a.num_nodes(), b.num_nodes());
  // PointTreeNode has no padding (4 int32 and a double): memcmp compares radii bit for bit.
  EXPECT_EQ(std::memcmp(a.nodes().data(), b.nodes().data(), a.nodes().size_bytes()), 0);
  ASSERT_EQ(a.num_points(), b.num_points());
  const auto n = static_cast<std::size_t>(a.num_points());
  EXPECT_EQ(std::memcmp(a.pointshell().points.data(), b.pointshell().points.data(), 24 * n), 0);
  EXPECT_EQ(std::memcmp(a.pointshell().normals.data(), b.pointshell().normals.data(), 24 * n), 0);
  EXPECT_EQ(a.pointshell().level_ends, b.pointshell().level_ends);
  for (Eigen::Index s = 0; s < a.num_points(); ++s) {
    ASSERT_EQ(a.source_index(s), b.source_index(s)) << s;
  }
}

void expect_bit_identical(const DeformablePointTree& a, const DeformablePointTree& b) {
  expect_same_point_tree(a.tree(), b.tree());
  ASSERT_EQ(a.dimension(), b.dimension());
  const auto entries = static_cast<std::size_t>(3 * a.dimension() * a.tree().num_points());
  EXPECT_EQ(
      std::memcmp(a.displacement_modes(0).data(), b.displacement_modes(0).data(), 8 * entries), 0);
  EXPECT_EQ(std::memcmp(a.normal_modes(0).data(), b.normal_modes(0).data(), 8 * entries), 0);
  const auto coefficients = static_cast<std::size_t>(a.dimension());
  for (Eigen::Index node = 0; node < a.tree().num_internal_nodes(); ++node) {
    ASSERT_EQ(std::memcmp(a.radius_coefficients(node).data(), b.radius_coefficients(node).data(),
                          8 * coefficients),
              0)
        << node;
  }
}

TEST(PointTreeFile, DeformableRoundTripIsBitExact) {
  const DeformablePointTree& tree = large_tree();
  // The tree renumbers points, so the file must restore a non-trivial source order.
  bool permuted = false;
  for (Eigen::Index s = 0; s < tree.tree().num_points(); ++s) {
    permuted = permuted || tree.tree().source_index(s) != s;
  }
  ASSERT_TRUE(permuted);

  const auto file = test::scratch_file("tree.khztree");
  write_deformable_point_tree(file, tree);
  expect_bit_identical(read_deformable_point_tree(file), tree);
  expect_bit_identical(parse_deformable_point_tree(test::read_bytes(file), "memory"), tree);
  // Header 20, pointshell 2·(16 + 24N) + 8 + 4L, fingerprint 8, r 4, modes 2·(8 + 24rN),
  // checksum 8.
  const auto n = static_cast<std::uintmax_t>(tree.tree().num_points());
  const auto levels = static_cast<std::uintmax_t>(tree.tree().num_levels());
  const auto r = static_cast<std::uintmax_t>(tree.dimension());
  EXPECT_EQ(std::filesystem::file_size(file),
            20 + 2 * (16 + 24 * n) + 8 + 4 * levels + 12 + 2 * (8 + 24 * r * n) + 8);
}

TEST(PointTreeFile, RigidTreeRoundTripsThroughItsPointshellFile) {
  const PointTree& tree = large_tree().tree();
  const auto file = test::scratch_file("rigid.khzshell");
  write_pointshell(file, source_pointshell(tree));
  const PointTree read(read_pointshell(file));
  expect_same_point_tree(read, tree);
  EXPECT_EQ(point_tree_fingerprint(read), point_tree_fingerprint(tree));
}

TEST(PointTreeFile, RejectsDamagedAndWrongKindFiles) {
  const auto file = test::scratch_file("damaged.khztree");
  const DeformablePointTree small = make_tree(60, 4, 2);
  write_deformable_point_tree(file, small);
  const std::string good = test::read_bytes(file);

  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x01;
  write_bytes(file, flipped);
  EXPECT_TRUE(test::throws_with_message(
      [&] { read_deformable_point_tree(file); },
      "byte " + std::to_string(good.size() - 8) + ": checksum mismatch: file is corrupted"));
  write_bytes(file, good.substr(0, good.size() - 100));
  EXPECT_TRUE(
      test::throws_with_message([&] { read_deformable_point_tree(file); }, "file ends early"));
  std::string newer = good;
  newer[8] = 2;
  write_bytes(file, newer);
  EXPECT_TRUE(test::throws_with_message([&] { read_deformable_point_tree(file); },
                                        "byte 8: written by a newer version 2"));
  // A pointshell file is not a tree file, nor the other way round.
  const auto shell_file = test::scratch_file("shell.khzshell");
  write_pointshell(shell_file, source_pointshell(small.tree()));
  EXPECT_TRUE(test::throws_with_message([&] { read_deformable_point_tree(shell_file); },
                                        "byte 0: not a Kilohertz deformable point tree file"));
  write_bytes(file, good);
  EXPECT_TRUE(test::throws_with_message([&] { read_pointshell(file); },
                                        "byte 0: not a Kilohertz pointshell file"));
  EXPECT_THROW(read_deformable_point_tree(test::scratch_file("missing.khztree")), IoError);
  EXPECT_THROW(write_deformable_point_tree(test::scratch_file("no/such/dir/x.khztree"), small),
               IoError);
}

/// A container with a valid envelope around a payload the test composes value by value.
struct Payload {
  Pointshell shell;
  std::uint64_t fingerprint = 0;
  std::int32_t dimension = 2;
  std::vector<double> displacement;
  std::vector<double> normal;

  explicit Payload(const DeformablePointTree& tree)
      : shell(source_pointshell(tree.tree())),
        fingerprint(point_tree_fingerprint(tree.tree())),
        dimension(static_cast<std::int32_t>(tree.dimension())) {
    const auto entries = static_cast<std::size_t>(3 * tree.dimension() * tree.tree().num_points());
    displacement.assign(tree.displacement_modes(0).data(),
                        tree.displacement_modes(0).data() + entries);
    normal.assign(tree.normal_modes(0).data(), tree.normal_modes(0).data() + entries);
  }

  std::string bytes() const {
    reduced::ContainerWriter writer(point_tree_file_format);
    append_pointshell(writer, shell);
    writer.write_u64(fingerprint);
    writer.write_i32(dimension);
    writer.write_doubles(displacement);
    writer.write_doubles(normal);
    return writer.bytes();
  }
};

TEST(PointTreeFile, ValidatesEveryValueWithItsByteOffset) {
  const DeformablePointTree tree = make_tree(60, 4, 2);
  const auto rejected = [](const Payload& payload, const std::string& message) {
    return test::throws_with_message(
        [&] { parse_deformable_point_tree(payload.bytes(), "f.khztree"); },
        "f.khztree: " + message);
  };
  EXPECT_NO_THROW(parse_deformable_point_tree(Payload(tree).bytes(), "f.khztree"));
  const auto n = static_cast<std::size_t>(tree.tree().num_points());
  const auto levels = static_cast<std::size_t>(tree.tree().num_levels());
  const std::size_t fingerprint_at = 20 + 2 * (16 + 24 * n) + 8 + 4 * levels;
  const std::size_t dimension_at = fingerprint_at + 8;
  const std::size_t displacement_at = dimension_at + 4;
  const std::size_t normal_at = displacement_at + 8 + 8 * 6 * n;
  const auto at = [](std::size_t offset) { return "byte " + std::to_string(offset) + ": "; };

  // The embedded pointshell is checked as in a pointshell file.
  reduced::ContainerWriter forged(point_tree_file_format);
  forged.write_matrix(Eigen::MatrixXd::Zero(2, 2));
  EXPECT_TRUE(
      test::throws_with_message([&] { parse_deformable_point_tree(forged.bytes(), "f.khztree"); },
                                "f.khztree: byte 20: points have 2 columns, expected 3"));
  Payload p(tree);
  p.dimension = 0;
  EXPECT_TRUE(rejected(p, at(dimension_at) + "the reduced dimension must be at least 1, got 0"));
  p = Payload(tree);
  p.dimension = 3;  // the arrays hold 3·2 per point
  EXPECT_TRUE(rejected(p, at(displacement_at) + "the displacement modes: " + std::to_string(6 * n) +
                              " entries, expected " + std::to_string(9 * n) + " (3r per point)"));
  p = Payload(tree);
  p.normal.pop_back();
  EXPECT_TRUE(rejected(p, at(normal_at) + "the normal modes: " + std::to_string(6 * n - 1) +
                              " entries, expected " + std::to_string(6 * n)));
  p = Payload(tree);
  p.displacement[6 * 3 + 4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(rejected(p, at(displacement_at + 8 + 8 * 22) +
                              "the displacement modes: entry 4 of point 3 is not finite"));
  p = Payload(tree);
  p.normal[1] = -std::numeric_limits<double>::infinity();
  EXPECT_TRUE(
      rejected(p, at(normal_at + 8 + 8) + "the normal modes: entry 1 of point 0 is not finite"));
  p = Payload(tree);
  p.fingerprint ^= 1;  // a tree built differently from the one read
  EXPECT_TRUE(rejected(
      p,
      at(fingerprint_at) + "the point tree rebuilt from the pointshell has topology fingerprint"));
}

}  // namespace
}  // namespace khz::contact
