#pragma once
// Test helpers: locating data files, scratch files, and checking error messages.

#include <khz/reduced/errors.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>

namespace khz::test {

/// Path of one of CGAL's demo meshes, e.g. cgal_mesh("dino.off"). Throws if it is missing
/// (a missing data file is a failure, never a skip).
std::filesystem::path cgal_mesh(std::string_view name);
/// Path of a committed test file under tests/data, e.g. test_file("malformed/off/empty.off").
std::filesystem::path test_file(std::string_view relative);
/// A fresh path in the scratch directory, unique to the running test.
std::filesystem::path scratch_file(std::string_view name);
/// A fresh path for a directory in the scratch directory, unique to the running test: an
/// earlier directory there is removed with its contents (scratch_file() clears files only); the
/// caller creates it, or lets the code under test do so.
std::filesystem::path scratch_directory(std::string_view name);
/// Whole content of a file (throws khz::reduced::IoError).
std::string read_bytes(const std::filesystem::path& file);

/// Succeeds if `action` throws an exception of type E whose what() contains `expected`.
template <typename E = reduced::ParseError, typename Action>
::testing::AssertionResult throws_with_message(Action&& action, std::string_view expected) {
  try {
    action();
  } catch (const E& error) {
    const std::string message = error.what();
    if (message.find(expected) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "message \"" << message << "\" lacks \"" << expected << "\"";
  } catch (const std::exception& error) {
    return ::testing::AssertionFailure() << "threw the wrong type: " << error.what();
  }
  return ::testing::AssertionFailure() << "did not throw (expected \"" << expected << "\")";
}

/// A committed malformed file and the text its ParseError must contain (location included).
struct MalformedFile {
  const char* file;     ///< Name inside the corpus folder.
  const char* message;  ///< Expected substring of what(), e.g. "empty.off:1: file ends early".
};

/// Checks a malformed corpus: `parse(path)` must throw a ParseError containing each case's
/// message, and every file in tests/data/<folder> must have a case (none goes untested).
void expect_corpus_rejected(std::string_view folder, std::span<const MalformedFile> cases,
                            const std::function<void(const std::filesystem::path&)>& parse);

}  // namespace khz::test
