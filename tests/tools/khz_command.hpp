#pragma once
// Running the real khz executable from a test and reading what it printed. KHZ_TOOL_PATH (the
// khz executable) comes from tests/CMakeLists.txt, which the test target must be given there.

#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <sstream>
#include <string>

namespace khz::test {

/// What one run of khz did.
struct KhzRun {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};

/// Runs `khz arguments` through the shell (quote paths in `arguments`), capturing its output
/// in the running test's scratch space.
inline KhzRun khz(const std::string& arguments) {
  const std::filesystem::path output = scratch_file("khz-output.txt");
  const std::string command =
      std::string("\"") + KHZ_TOOL_PATH + "\" " + arguments + " > \"" + output.string() + "\" 2>&1";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_bytes(output)};
}

/// Succeeds if some line of `run`'s output contains every one of `words`; a failure shows the
/// whole output.
inline ::testing::AssertionResult has_line_with(const KhzRun& run,
                                                std::initializer_list<std::string> words) {
  std::istringstream lines(run.output);
  for (std::string line; std::getline(lines, line);) {
    bool all = true;
    for (const std::string& word : words) all = all && line.find(word) != std::string::npos;
    if (all) return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "no line holds all the words; khz printed:\n"
                                       << run.output;
}

}  // namespace khz::test
