#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

// xxHash compiled into this test, so the checksum is recomputed independently of the library.
#define XXH_INLINE_ALL
// Its portable scalar code (XXH_SCALAR), not the library's SIMD paths: independent, and free of
// GCC 12's false -Wuninitialized in the AVX-512 intrinsics under -march=native.
#define XXH_VECTOR 0
#include <xxhash.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

constexpr ContainerFormat test_format{"KHZTEST1", "Kilohertz test file", 2};

/// Reads `bytes` as a test_format container named "t.bin" in messages.
ContainerReader reader_of(const std::string& bytes, const ContainerFormat& format = test_format) {
  return ContainerReader(bytes, "t.bin", format);
}

/// A container whose payload is the single u64 `value`, followed by `extra` payload bytes.
std::string with_u64(std::uint64_t value, std::size_t extra = 0) {
  ContainerWriter writer(test_format);
  writer.write_u64(value);
  for (std::size_t i = 0; i < extra; ++i) writer.write_u32(0);  // 4 bytes each
  return writer.bytes();
}

TEST(BinaryContainer, WritesHeaderPayloadAndChecksumLittleEndian) {
  ContainerWriter writer(test_format);
  writer.write_u32(0x01020304u);
  const std::string bytes = writer.bytes();
  ASSERT_EQ(bytes.size(), container_header_bytes + 4 + container_checksum_bytes);
  EXPECT_EQ(bytes.substr(0, 8), "KHZTEST1");
  EXPECT_EQ(bytes.substr(8, 4), std::string("\x02\0\0\0", 4));           // version 2
  EXPECT_EQ(bytes.substr(12, 8), std::string("\x20\0\0\0\0\0\0\0", 8));  // length 32
  EXPECT_EQ(bytes.substr(20, 4), std::string("\x04\x03\x02\x01", 4));    // payload
  EXPECT_EQ(writer.bytes(), bytes);                                      // bytes() is repeatable
}

TEST(BinaryContainer, ChecksumIsXxh3OfEverythingBefore) {
  // The test computes XXH3 itself (xxHash inlined, see the include) so the check does not go
  // through the library; the empty-input answer is the specification's known value.
  ASSERT_EQ(XXH3_64bits("", 0), 0x2d06800538d394c2u);
  ContainerWriter writer(test_format);
  writer.write_string("payload");
  const std::string bytes = writer.bytes();
  const std::size_t end = bytes.size() - container_checksum_bytes;
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + end, 8);  // the test host is little-endian
  EXPECT_EQ(stored, XXH3_64bits(bytes.data(), end));
}

TEST(BinaryContainer, RoundTripsEveryValueTypeBitExactly) {
  const std::vector<double> doubles = {0.0,
                                       -0.0,
                                       1e-310,
                                       -std::numeric_limits<double>::max(),
                                       std::numeric_limits<double>::infinity(),
                                       0.1};
  const std::vector<int> ints = {0, -1, std::numeric_limits<int>::min(),
                                 std::numeric_limits<int>::max()};
  Eigen::MatrixXd matrix(3, 2);
  matrix << 1, 2, 3, 4, 5, std::nan("");
  ContainerWriter writer(test_format);
  writer.write_u32(4000000000u);
  writer.write_u64(std::numeric_limits<std::uint64_t>::max());
  writer.write_i32(-7);
  writer.write_f64(-0.0);
  writer.write_string("Grüße\n\0end");
  writer.write_string(std::string("a\0b", 3));
  writer.write_doubles(doubles);
  writer.write_ints(ints);
  writer.write_matrix(matrix);
  writer.write_matrix(matrix.block(1, 0, 2, 2));  // a strided block is written column by column
  writer.write_doubles({});

  ContainerReader reader = reader_of(writer.bytes());
  EXPECT_EQ(reader.version(), 2u);
  EXPECT_EQ(reader.read_u32("u32"), 4000000000u);
  EXPECT_EQ(reader.read_u64("u64"), std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(reader.read_i32("i32"), -7);
  EXPECT_TRUE(std::signbit(reader.read_f64("f64")));
  EXPECT_EQ(reader.read_string("string"), "Grüße\n");  // a C string literal stops at \0
  EXPECT_EQ(reader.read_string("string"), std::string("a\0b", 3));
  const std::vector<double> doubles_read = reader.read_doubles("doubles");
  ASSERT_EQ(doubles_read.size(), doubles.size());
  EXPECT_EQ(std::memcmp(doubles_read.data(), doubles.data(), doubles.size() * 8), 0);
  EXPECT_EQ(reader.read_ints("ints"), ints);
  const Eigen::MatrixXd matrix_read = reader.read_matrix("matrix");
  ASSERT_EQ(matrix_read.rows(), 3);
  ASSERT_EQ(matrix_read.cols(), 2);
  EXPECT_EQ(std::memcmp(matrix_read.data(), matrix.data(), 6 * 8), 0);
  const Eigen::MatrixXd block = matrix.block(1, 0, 2, 2);  // holds the NaN
  EXPECT_EQ(std::memcmp(reader.read_matrix("block").data(), block.data(), 4 * 8), 0);
  EXPECT_TRUE(reader.read_doubles("empty").empty());
  EXPECT_EQ(reader.remaining_bytes(), 0u);
  reader.finish("the test values");
}

TEST(BinaryContainer, ReportsWhereValuesStart) {
  ContainerWriter writer(test_format);
  writer.write_u32(1);
  writer.write_ints(std::vector<int>{1, 2, 3});
  ContainerReader reader = reader_of(writer.bytes());
  EXPECT_EQ(reader.offset(), 20u);
  reader.read_u32("u32");
  EXPECT_EQ(reader.value_offset(), 20u);
  reader.read_ints("ints");
  EXPECT_EQ(reader.value_offset(), 32u);  // after the u32 and the 8-byte count
  EXPECT_EQ(reader.offset(), 44u);
  EXPECT_TRUE(test::throws_with_message([&] { reader.fail_at(36, "second item"); },
                                        "t.bin: byte 36: second item"));
}

TEST(BinaryContainer, ReadsOlderVersionsAndRejectsNewerOnes) {
  const std::string bytes = ContainerWriter(test_format).bytes();  // version 2
  EXPECT_EQ(reader_of(bytes, {"KHZTEST1", "Kilohertz test file", 3}).version(), 2u);
  EXPECT_TRUE(test::throws_with_message(
      [&] {
        reader_of(bytes, {"KHZTEST1", "Kilohertz test file", 1});
      },
      "t.bin: byte 8: written by a newer version 2; this build reads up to 1"));
}

TEST(BinaryContainer, RejectsFormatsWithoutAnEightByteMagic) {
  EXPECT_TRUE(test::throws_with_message<Error>(
      [] {
        ContainerWriter({"SHORT", "short file", 1});
      },
      "the magic must be 8 bytes, not 5"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      [] {
        ContainerWriter({"KHZTEST1", "test file", 0});
      },
      "versions start at 1"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      [] {
        ContainerReader("", "t.bin", {"TOO LONG!", "long file", 1});
      },
      "the magic must be 8 bytes, not 9"));
}

TEST(BinaryContainer, RejectsCountsThatExceedTheRemainingBytes) {
  // Each payload is a lone u64 read as a length: nothing may be allocated from it.
  const std::uint64_t huge = std::uint64_t{1} << 62;
  EXPECT_TRUE(test::throws_with_message(
      [&] { reader_of(with_u64(huge, 1)).read_string("the name"); },
      "t.bin: byte 20: the name: 4611686018427387904 bytes do not fit in the 4 bytes that "
      "remain"));
  EXPECT_TRUE(test::throws_with_message(
      [&] { reader_of(with_u64(5, 2)).read_doubles("the weights"); },
      "t.bin: byte 20: the weights: 5 items of 8 bytes do not fit in the 8 bytes that remain"));
  EXPECT_TRUE(test::throws_with_message(
      [&] { reader_of(with_u64(3, 2)).read_ints("the indices"); },
      "t.bin: byte 20: the indices: 3 items of 4 bytes do not fit in the 8 bytes that remain"));
  EXPECT_TRUE(test::throws_with_message(
      [&] { reader_of(with_u64(std::numeric_limits<std::uint64_t>::max())).read_ints("ids"); },
      "t.bin: byte 20: ids: 18446744073709551615 items of 4 bytes do not fit in the 0 bytes"));
  // Exactly enough is accepted.
  EXPECT_EQ(reader_of(with_u64(2, 2)).read_ints("two").size(), 2u);
}

TEST(BinaryContainer, RejectsMatrixShapesThatExceedLimitsOrBytes) {
  ContainerWriter large(test_format);
  large.write_u64(100000);
  large.write_u64(100000);
  EXPECT_TRUE(test::throws_with_message(
      [&] { reader_of(large.bytes()).read_matrix("U"); },
      "t.bin: byte 20: U: 100000×100000 entries of 8 bytes do not fit in the 0 bytes that "
      "remain"));
  ContainerWriter absurd(test_format);
  absurd.write_u64(0);
  absurd.write_u64(std::uint64_t{1} << 40);  // zero entries, but an absurd column count
  EXPECT_TRUE(test::throws_with_message(
      [&] { reader_of(absurd.bytes()).read_matrix("U"); },
      "t.bin: byte 20: U: 0×1099511627776 exceeds the dimension limit of 2147483647"));
}

TEST(BinaryContainer, RejectsReadingPastThePayload) {
  ContainerWriter writer(test_format);
  writer.write_u32(1);
  ContainerReader reader = reader_of(writer.bytes());
  EXPECT_TRUE(test::throws_with_message([&] { reader.read_u64("the count"); },
                                        "t.bin: byte 20: file ends early: expected the count "
                                        "(8 bytes, 4 left)"));
  reader.read_u32("u32");
  EXPECT_TRUE(test::throws_with_message([&] { reader.read_string("the name"); },
                                        "t.bin: byte 24: file ends early: expected the length "
                                        "of the name (8 bytes, 0 left)"));
}

TEST(BinaryContainer, FinishRejectsUnreadBytes) {
  ContainerReader reader = reader_of(with_u64(1, 1));
  reader.read_u64("u64");
  EXPECT_TRUE(test::throws_with_message([&] { reader.finish("the counts"); },
                                        "t.bin: byte 28: 4 unread bytes after the counts"));
}

TEST(BinaryContainer, WriteFileReplacesAtomicallyAndLeavesNoTemporaryFiles) {
  const std::filesystem::path file = test::scratch_file("replace.bin");
  ContainerWriter first(test_format);
  first.write_u32(1);
  first.write_file(file);
  ContainerWriter second(test_format);
  second.write_string("second version");
  second.write_file(file);
  EXPECT_EQ(test::read_bytes(file), second.bytes());
  EXPECT_EQ(ContainerReader::open(file, test_format).read_string("text"), "second version");
  int entries = 0;
  for ([[maybe_unused]] const auto& entry :
       std::filesystem::directory_iterator(file.parent_path())) {
    ++entries;
  }
  EXPECT_EQ(entries, 1);  // no temporary left behind
}

TEST(BinaryContainer, WriteFileNamesThePathAndReason) {
  const std::filesystem::path file = test::scratch_file("missing") / "dir" / "x.bin";
  EXPECT_TRUE(test::throws_with_message<IoError>(
      [&] { ContainerWriter(test_format).write_file(file); },
      file.string() + ": cannot create a temporary file in " + file.parent_path().string() +
          ": No such file or directory"));
  const std::filesystem::path directory = test::scratch_file("a_directory");
  std::filesystem::create_directories(directory);
  EXPECT_TRUE(test::throws_with_message<IoError>(
      [&] { ContainerWriter(test_format).write_file(directory); },
      directory.string() + ": cannot rename"));
  int entries = 0;
  for ([[maybe_unused]] const auto& entry :
       std::filesystem::directory_iterator(directory.parent_path())) {
    ++entries;
  }
  EXPECT_EQ(entries, 1);  // the directory itself; the temporary was removed
}

TEST(BinaryContainer, OpenReportsUnreadableFiles) {
  const std::filesystem::path file = test::scratch_file("absent.bin");
  EXPECT_TRUE(test::throws_with_message<IoError>([&] { ContainerReader::open(file, test_format); },
                                                 file.string() + ": cannot open"));
}

}  // namespace
}  // namespace khz::reduced
