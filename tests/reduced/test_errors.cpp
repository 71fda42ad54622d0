#include <khz/reduced/errors.hpp>

#include <gtest/gtest.h>

namespace khz::reduced {
namespace {

TEST(ParseError, TextLocationPrefixesMessage) {
  const ParseError error = ParseError::at_line("mesh.off", 12, "expected a vertex index");
  EXPECT_STREQ(error.what(), "mesh.off:12: expected a vertex index");
  EXPECT_EQ(error.line(), 12);
  EXPECT_EQ(error.byte_offset(), -1);
  EXPECT_EQ(error.source(), "mesh.off");
  EXPECT_EQ(error.message(), "expected a vertex index");
}

TEST(ParseError, BinaryLocationPrefixesMessage) {
  const ParseError error = ParseError::at_byte("mesh.stl", 84, "file ends early");
  EXPECT_STREQ(error.what(), "mesh.stl: byte 84: file ends early");
  EXPECT_EQ(error.line(), -1);
  EXPECT_EQ(error.byte_offset(), 84);
}

TEST(ParseError, IsCaughtAsKilohertzError) {
  EXPECT_THROW(throw ParseError::at_line("f", 1, "x"), Error);
  EXPECT_THROW(throw MeshError("x", 3), Error);
  EXPECT_THROW(throw IoError("x"), std::runtime_error);
}

}  // namespace
}  // namespace khz::reduced
