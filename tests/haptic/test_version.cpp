#include <khz/contact/version.hpp>
#include <khz/haptic/version.hpp>
#include <khz/reduced/version.hpp>

#include <gtest/gtest.h>

namespace {

// Headers and binaries of one build must agree; a mismatch means mixed installs.
TEST(LibraryVersion, BinariesMatchHeaders) {
  EXPECT_STREQ(khz::reduced::library_version(), KHZ_REDUCED_VERSION_STRING);
  EXPECT_STREQ(khz::contact::library_version(), KHZ_CONTACT_VERSION_STRING);
  EXPECT_STREQ(khz::haptic::library_version(), KHZ_HAPTIC_VERSION_STRING);
}

}  // namespace
