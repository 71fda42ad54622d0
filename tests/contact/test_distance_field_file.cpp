#include <khz/contact/common.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/io/distance_field_file.hpp>
#include <khz/contact/io/distance_field_vti.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace khz::contact {
namespace {

void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// A small grid with awkward values: ±0, a subnormal, extremes, and a negative origin.
DistanceGrid awkward_grid(bool is_signed) {
  const GridGeometry geometry{Eigen::Vector3d(-1.25, 0.1, 3e-7), 0.3, 3};
  std::vector<float> values(64);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.37f * static_cast<float>(i);
  values[1] = is_signed ? -0.0f : 0.0f;
  values[2] = std::numeric_limits<float>::denorm_min();
  values[3] = std::numeric_limits<float>::max();
  if (is_signed) values[4] = -std::numeric_limits<float>::max();
  return DistanceGrid(geometry, std::move(values), is_signed);
}

void expect_bit_identical(const DistanceGrid& a, const DistanceGrid& b) {
  EXPECT_EQ(a.is_signed(), b.is_signed());
  EXPECT_EQ(a.geometry().cells, b.geometry().cells);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.geometry().origin[axis]),
              std::bit_cast<std::uint64_t>(b.geometry().origin[axis]));
  }
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.geometry().spacing),
            std::bit_cast<std::uint64_t>(b.geometry().spacing));
  ASSERT_EQ(a.values().size(), b.values().size());
  EXPECT_EQ(std::memcmp(a.values().data(), b.values().data(), a.values().size_bytes()), 0);
}

TEST(DistanceFieldFile, RoundTripIsBitExact) {
  DistanceFieldOptions options;
  options.cells = 24;
  const DistanceGrid grids[] = {awkward_grid(true), awkward_grid(false),
                                signed_distance_field(test::uv_sphere(16, 9), options)};
  for (const DistanceGrid& grid : grids) {
    const auto file = test::scratch_file("grid.khzsdf");
    write_distance_field(file, grid);
    expect_bit_identical(read_distance_field(file), grid);
    expect_bit_identical(parse_distance_field(test::read_bytes(file), "memory"), grid);
    // 20 header bytes, 4 + 32 + 4 of geometry, n planes of 8 + 4n², 8 checksum bytes.
    const auto n = static_cast<std::uintmax_t>(grid.geometry().nodes_per_axis());
    EXPECT_EQ(std::filesystem::file_size(file), 20 + 40 + n * (8 + 4 * n * n) + 8);
  }
}

TEST(DistanceFieldFile, RejectsDamagedFiles) {
  const auto file = test::scratch_file("damaged.khzsdf");
  write_distance_field(file, awkward_grid(true));
  const std::string good = test::read_bytes(file);

  std::string flipped = good;
  flipped[100] ^= 0x10;
  write_bytes(file, flipped);
  EXPECT_TRUE(test::throws_with_message(
      [&] { read_distance_field(file); },
      "byte " + std::to_string(good.size() - 8) + ": checksum mismatch: file is corrupted"));
  write_bytes(file, good.substr(0, good.size() - 13));
  EXPECT_TRUE(test::throws_with_message([&] { read_distance_field(file); }, "file ends early"));
  write_bytes(file, good + "x");
  EXPECT_TRUE(test::throws_with_message([&] { read_distance_field(file); },
                                        "1 bytes after the end of the file"));
  std::string magic = good;
  magic.replace(0, 8, "KHZBASIS");
  write_bytes(file, magic);
  EXPECT_TRUE(test::throws_with_message([&] { read_distance_field(file); },
                                        "byte 0: not a Kilohertz distance field file"));
  std::string newer = good;
  newer[8] = 2;
  write_bytes(file, newer);
  EXPECT_TRUE(test::throws_with_message([&] { read_distance_field(file); },
                                        "byte 8: written by a newer version 2"));
  EXPECT_THROW(read_distance_field(test::scratch_file("missing.khzsdf")), IoError);
  EXPECT_THROW(write_distance_field(test::scratch_file("no/such/dir/x.khzsdf"), awkward_grid(true)),
               IoError);
}

/// A container with a valid envelope around a payload the test composes value by value.
struct Payload {
  std::uint32_t flags = 1;
  double origin[3] = {0.0, 0.0, 0.0};
  double spacing = 0.5;
  std::int32_t cells = 1;
  std::vector<std::vector<float>> planes = {{1, 2, 3, 4}, {5, 6, 7, 8}};
  bool extra = false;

  std::string bytes() const {
    reduced::ContainerWriter writer(distance_field_file_format);
    writer.write_u32(flags);
    for (const double x : origin) writer.write_f64(x);
    writer.write_f64(spacing);
    writer.write_i32(cells);
    for (const auto& plane : planes) {
      std::vector<int> bits;
      for (const float value : plane) bits.push_back(std::bit_cast<int>(value));
      writer.write_ints(bits);
    }
    if (extra) writer.write_u32(7);
    return writer.bytes();
  }
};

TEST(DistanceFieldFile, ValidatesEveryValueWithItsByteOffset) {
  const auto rejected = [](const Payload& payload, const std::string& message) {
    return test::throws_with_message([&] { parse_distance_field(payload.bytes(), "f.khzsdf"); },
                                     "f.khzsdf: " + message);
  };
  EXPECT_NO_THROW(parse_distance_field(Payload{}.bytes(), "f.khzsdf"));
  Payload p;
  p.flags = 3;
  EXPECT_TRUE(rejected(p, "byte 20: unknown flags 3"));
  p = {};
  p.origin[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(rejected(p, "byte 32: the origin's y is not finite"));
  p = {};
  p.spacing = 0.0;
  EXPECT_TRUE(rejected(p, "byte 48: the spacing must be positive"));
  p.spacing = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(rejected(p, "byte 48: the spacing must be positive"));
  p = {};
  p.cells = 0;
  EXPECT_TRUE(rejected(p, "byte 56: invalid cell count 0"));
  p.cells = 100000;  // refused from the size, before 4·10¹⁵ bytes are allocated
  EXPECT_TRUE(rejected(p, "byte 56: 100000³ cells need 100001 planes"));
  p = {};
  p.planes[1].push_back(9);
  p.planes[0].pop_back();
  EXPECT_TRUE(rejected(p, "byte 60: plane 0 has 3 values, expected 4"));
  p = {};
  p.planes[1][2] = std::numeric_limits<float>::infinity();  // node (0, 1, 1)
  // Plane 1 starts at 60 + 8 + 16 = 84; its values at 92; item 2 at 100.
  EXPECT_TRUE(rejected(p, "byte 100: node (0, 1, 1) = inf is not finite"));
  p = {};
  p.flags = 0;
  p.planes[0][1] = -0.5f;
  EXPECT_TRUE(rejected(p, "byte 72: node (1, 0, 0) = -0.500000 is negative in an unsigned field"));
  p = {};
  p.extra = true;
  EXPECT_TRUE(rejected(p, "byte 108: 4 unread bytes after the node values"));
}

/// Decodes RFC 4648 base64, skipping whitespace.
std::vector<unsigned char> decode_base64(const std::string& text) {
  std::vector<unsigned char> bytes;
  std::uint32_t bits = 0;
  int count = 0;
  for (const char c : text) {
    int value;
    if (c >= 'A' && c <= 'Z')
      value = c - 'A';
    else if (c >= 'a' && c <= 'z')
      value = c - 'a' + 26;
    else if (c >= '0' && c <= '9')
      value = c - '0' + 52;
    else if (c == '+')
      value = 62;
    else if (c == '/')
      value = 63;
    else
      continue;  // whitespace and padding
    bits = (bits << 6) | static_cast<std::uint32_t>(value);
    if (++count == 4) {
      bytes.push_back(static_cast<unsigned char>(bits >> 16));
      bytes.push_back(static_cast<unsigned char>(bits >> 8));
      bytes.push_back(static_cast<unsigned char>(bits));
      bits = 0;
      count = 0;
    }
  }
  if (count == 3) {
    bytes.push_back(static_cast<unsigned char>(bits >> 10));
    bytes.push_back(static_cast<unsigned char>(bits >> 2));
  } else if (count == 2) {
    bytes.push_back(static_cast<unsigned char>(bits >> 4));
  }
  return bytes;
}

std::string data_array_text(const std::string& document) {
  const auto open = document.find('>', document.find("<DataArray")) + 1;
  return document.substr(open, document.find("</DataArray>") - open);
}

TEST(DistanceFieldVti, Base64HoldsTheByteCountAndTheExactValues) {
  const DistanceGrid grid = awkward_grid(true);
  const std::string vti = format_distance_field_vti(grid);
  EXPECT_NE(vti.find("<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" "
                     "header_type=\"UInt64\">"),
            std::string::npos);
  EXPECT_NE(
      vti.find("WholeExtent=\"0 3 0 3 0 3\" Origin=\"-1.25 0.1 3e-07\" Spacing=\"0.3 0.3 0.3\""),
      std::string::npos);
  EXPECT_NE(vti.find("<DataArray type=\"Float32\" Name=\"signed_distance\" format=\"binary\""),
            std::string::npos);
  // One line between the tags: VTK 9.1's vtkXMLImageDataReader does not skip line breaks
  // inside base64 data (checked against it; it reads this layout back exactly).
  const std::string data = data_array_text(vti);
  EXPECT_EQ(std::count(data.begin(), data.end(), '\n'), 2);
  const std::vector<unsigned char> bytes = decode_base64(data);
  ASSERT_EQ(bytes.size(), 8 + grid.values().size_bytes());
  std::uint64_t count;
  std::memcpy(&count, bytes.data(), 8);
  EXPECT_EQ(count, grid.values().size_bytes());
  EXPECT_EQ(std::memcmp(bytes.data() + 8, grid.values().data(), grid.values().size_bytes()), 0);
  // Every length modulo 3 of the encoded stream pads correctly.
  for (int cells = 1; cells <= 3; ++cells) {
    const DistanceGrid small(
        GridGeometry{Eigen::Vector3d::Zero(), 1.0, cells},
        std::vector<float>(static_cast<std::size_t>((cells + 1) * (cells + 1) * (cells + 1)), 1.5f),
        false);
    EXPECT_EQ(decode_base64(data_array_text(format_distance_field_vti(small))).size(),
              8 + small.values().size_bytes());
  }
}

TEST(DistanceFieldVti, AsciiReadsBackToTheSameFloats) {
  const DistanceGrid grid = awkward_grid(false);
  const std::string vti = format_distance_field_vti(grid, VtiEncoding::ascii);
  EXPECT_NE(vti.find("Name=\"distance\" format=\"ascii\""), std::string::npos);
  std::istringstream numbers(data_array_text(vti));
  std::vector<float> values;
  for (std::string word; numbers >> word;) values.push_back(std::strtof(word.c_str(), nullptr));
  ASSERT_EQ(values.size(), grid.values().size());
  EXPECT_EQ(std::memcmp(values.data(), grid.values().data(), grid.values().size_bytes()), 0);
}

TEST(DistanceFieldVti, WritesTheFileAtomically) {
  const DistanceGrid grid = awkward_grid(true);
  const auto file = test::scratch_file("grid.vti");
  write_distance_field_vti(file, grid);
  EXPECT_EQ(test::read_bytes(file), format_distance_field_vti(grid));
  write_distance_field_vti(file, grid, VtiEncoding::ascii);
  EXPECT_EQ(test::read_bytes(file), format_distance_field_vti(grid, VtiEncoding::ascii));
  for (const auto& entry : std::filesystem::directory_iterator(file.parent_path())) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos);
  }
  EXPECT_THROW(write_distance_field_vti(test::scratch_file("no/such/dir/x.vti"), grid), IoError);
}

}  // namespace
}  // namespace khz::contact
