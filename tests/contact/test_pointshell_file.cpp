#include <khz/contact/common.hpp>
#include <khz/contact/io/pointshell_file.hpp>
#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace khz::contact {
namespace {

void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Three points in two levels with awkward values: ±0, a subnormal, extremes.
Pointshell awkward_shell() {
  Pointshell shell;
  shell.points.resize(3, 3);
  shell.points << -0.0, std::numeric_limits<double>::denorm_min(), 1e300,  //
      -1.25, 0.1, 3e-7,                                                    //
      std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(), 0.0;
  shell.normals.resize(3, 3);
  shell.normals << 0.0, 0.0, -1.0,  //
      0.6, 0.8, 0.0,                //
      1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0);
  shell.level_ends = {1, 3};
  return shell;
}

void expect_bit_identical(const Pointshell& a, const Pointshell& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(b.normals.rows(), b.size());
  EXPECT_EQ(std::memcmp(a.points.data(), b.points.data(), sizeof(double) * 3 * a.size()), 0);
  EXPECT_EQ(std::memcmp(a.normals.data(), b.normals.data(), sizeof(double) * 3 * a.size()), 0);
  EXPECT_EQ(a.level_ends, b.level_ends);
}

TEST(PointshellFile, RoundTripIsBitExact) {
  NestedLevelOptions options;
  options.schedule = LevelSchedule::quadrupling(10);
  const Pointshell shells[] = {
      awkward_shell(),
      nested_pointshell(random_pointshell(test::uv_sphere(16, 9), 700, 5), options)};
  for (const Pointshell& shell : shells) {
    const auto file = test::scratch_file("shell.khzshell");
    write_pointshell(file, shell);
    expect_bit_identical(read_pointshell(file), shell);
    expect_bit_identical(parse_pointshell(test::read_bytes(file), "memory"), shell);
    // 20 header bytes, two matrices of 16 + 24N, the level ends 8 + 4L, 8 checksum bytes.
    const auto n = static_cast<std::uintmax_t>(shell.size());
    EXPECT_EQ(std::filesystem::file_size(file),
              20 + 2 * (16 + 24 * n) + 8 + 4 * shell.level_ends.size() + 8);
  }
}

TEST(PointshellFile, RejectsDamagedFilesAndInvalidPointshells) {
  const auto file = test::scratch_file("damaged.khzshell");
  write_pointshell(file, awkward_shell());
  const std::string good = test::read_bytes(file);

  std::string flipped = good;
  flipped[60] ^= 0x10;
  write_bytes(file, flipped);
  EXPECT_TRUE(test::throws_with_message(
      [&] { read_pointshell(file); },
      "byte " + std::to_string(good.size() - 8) + ": checksum mismatch: file is corrupted"));
  write_bytes(file, good.substr(0, good.size() - 13));
  EXPECT_TRUE(test::throws_with_message([&] { read_pointshell(file); }, "file ends early"));
  write_bytes(file, good + "x");
  EXPECT_TRUE(test::throws_with_message([&] { read_pointshell(file); },
                                        "1 bytes after the end of the file"));
  std::string magic = good;
  magic.replace(0, 8, "KHZFIELD");
  write_bytes(file, magic);
  EXPECT_TRUE(test::throws_with_message([&] { read_pointshell(file); },
                                        "byte 0: not a Kilohertz pointshell file"));
  std::string newer = good;
  newer[8] = 2;
  write_bytes(file, newer);
  EXPECT_TRUE(test::throws_with_message([&] { read_pointshell(file); },
                                        "byte 8: written by a newer version 2"));
  EXPECT_THROW(read_pointshell(test::scratch_file("missing.khzshell")), IoError);
  EXPECT_THROW(write_pointshell(test::scratch_file("no/such/dir/x.khzshell"), awkward_shell()),
               IoError);
  // An invalid pointshell is refused before anything is written.
  Pointshell invalid = awkward_shell();
  invalid.level_ends = {3, 1};
  const auto never = test::scratch_file("invalid.khzshell");
  EXPECT_THROW(write_pointshell(never, invalid), Error);
  EXPECT_FALSE(std::filesystem::exists(never));
}

/// A container with a valid envelope around a payload the test composes value by value: two
/// points, two levels.
struct Payload {
  Eigen::MatrixXd points = Eigen::MatrixXd::Zero(2, 3);
  Eigen::MatrixXd normals = (Eigen::MatrixXd(2, 3) << 1, 0, 0, 0, 0, -1).finished();
  std::vector<int> ends = {1, 2};
  bool forged_rows = false;  // a points matrix claiming 10⁹ rows and nothing after it
  bool extra = false;

  std::string bytes() const {
    reduced::ContainerWriter writer(pointshell_file_format);
    if (forged_rows) {
      writer.write_u64(1'000'000'000);
      writer.write_u64(3);
      return writer.bytes();
    }
    writer.write_matrix(points);
    writer.write_matrix(normals);
    writer.write_ints(ends);
    if (extra) writer.write_u32(7);
    return writer.bytes();
  }
};

TEST(PointshellFile, ValidatesEveryValueWithItsByteOffset) {
  const auto rejected = [](const Payload& payload, const std::string& message) {
    return test::throws_with_message([&] { parse_pointshell(payload.bytes(), "f.khzshell"); },
                                     "f.khzshell: " + message);
  };
  EXPECT_NO_THROW(parse_pointshell(Payload{}.bytes(), "f.khzshell"));
  // Points at 20 (entries at 36), normals at 84 (entries at 100), level ends at 148 (items 156).
  Payload p;
  p.points = Eigen::MatrixXd::Zero(2, 2);
  EXPECT_TRUE(rejected(p, "byte 20: points have 2 columns, expected 3"));
  p = {};
  p.forged_rows = true;  // refused from the size, before 24 GB are allocated
  EXPECT_TRUE(rejected(p, "byte 20: points: 1000000000×3 entries of 8 bytes do not fit"));
  p = {};
  p.normals = Eigen::MatrixXd::Zero(3, 3);
  EXPECT_TRUE(rejected(p, "byte 84: there are 3 normals for 2 points"));
  p = {};
  p.points(1, 2) = std::numeric_limits<double>::quiet_NaN();  // column-major: 36 + 8·(2·2 + 1)
  EXPECT_TRUE(rejected(p, "byte 76: points: z of point 1 is not finite"));
  p = {};
  p.normals(0, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(rejected(p, "byte 116: normals: y of point 0 is not finite"));
  p = {};
  p.normals(1, 2) = -2.0;
  EXPECT_TRUE(rejected(p, "byte 108: the normal of point 1 has length 2.000000, not 1"));
  p = {};
  p.ends = {};
  EXPECT_TRUE(rejected(p, "byte 148: no levels"));
  p.ends = {0, 2};
  EXPECT_TRUE(rejected(p, "byte 156: level 0 ends at point 0, not after 0"));
  p.ends = {1, 1, 2};
  EXPECT_TRUE(rejected(p, "byte 160: level 1 ends at point 1, not after 1"));
  p.ends = {1};
  EXPECT_TRUE(rejected(p, "byte 156: the levels end at point 1, not at the 2 points"));
  p = {};
  p.extra = true;
  EXPECT_TRUE(rejected(p, "byte 164: 4 unread bytes after the level ends"));
}

}  // namespace
}  // namespace khz::contact
