#pragma once
// Running a program the tests compare against (Gmsh, TetGen, ...) and reading what it printed.
// Its path comes from find_program() in tests/CMakeLists.txt as a compile definition, empty when
// the program was missing at configure time: the test then fails, naming the package.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace khz::test {

/// What one run of a program did.
struct ProgramRun {
  int exit_code = -1;  ///< -1 if it did not exit normally (killed by a signal)
  std::string output;  ///< stdout and stderr together
};

/// `path` (a program found at configure time); throws, failing the test, when it is empty.
/// Defined out of line: with an inline definition the compiler would see a missing program's
/// test throw unconditionally and warn about the code after it.
std::string required_program(std::string_view path, std::string_view name,
                             std::string_view debian_package);

/// Where and with what a program runs, beyond run_program()'s defaults.
struct ProgramOptions {
  /// The directory it runs in (for programs that write files beside their input); empty: this
  /// process's.
  std::filesystem::path working_directory;
  /// "NAME=value" settings that replace the inherited ones (e.g. a program's own thread counts).
  std::vector<std::string> environment;
};

/// Runs `program arguments...` without a shell, standard input empty, its output captured in
/// the running test's scratch space. The child's environment is this one with
/// OMP_NUM_THREADS=1 and options.environment, so a run takes one core and its result does not
/// depend on the machine's. @throws std::runtime_error if it cannot be started.
ProgramRun run_program(const std::string& program, const std::vector<std::string>& arguments,
                       const ProgramOptions& options = {});

}  // namespace khz::test
