#include <khz/test/external_program.hpp>
#include <khz/test/fixtures.hpp>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

extern char** environ;

namespace khz::test {

std::string required_program(std::string_view path, std::string_view name,
                             std::string_view debian_package) {
  if (path.empty()) {
    throw std::runtime_error(std::string(name) +
                             " was not found when the build was configured: install the Debian "
                             "package " +
                             std::string(debian_package) +
                             " (scripts/setup-debian installs it) and re-run cmake");
  }
  return std::string(path);
}

ProgramRun run_program(const std::string& program, const std::vector<std::string>& arguments,
                       const ProgramOptions& options) {
  const std::filesystem::path log = scratch_file("program-output.txt");
  std::vector<std::string> strings{program};
  strings.insert(strings.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& s : strings) argv.push_back(s.data());
  argv.push_back(nullptr);

  std::vector<std::string> variables{"OMP_NUM_THREADS=1"};
  variables.insert(variables.end(), options.environment.begin(), options.environment.end());
  const auto is_set = [&](std::string_view variable) {
    const std::string_view name = variable.substr(0, variable.find('=') + 1);
    return std::any_of(variables.begin(), variables.end(),
                       [&](const std::string& set) { return set.starts_with(name); });
  };
  for (char** variable = environ; *variable != nullptr; ++variable) {
    if (!is_set(*variable)) variables.emplace_back(*variable);
  }
  std::vector<char*> envp;
  for (std::string& s : variables) envp.push_back(s.data());
  envp.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!options.working_directory.empty()) {
    posix_spawn_file_actions_addchdir_np(&actions, options.working_directory.c_str());
  }
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int error = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) {
    throw std::runtime_error("cannot start " + program + ": " + std::strerror(error));
  }
  int status = 0;
  while (waitpid(pid, &status, 0) != pid) {
    if (errno != EINTR) throw std::runtime_error("waitpid failed for " + program);
  }
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_bytes(log)};
}

}  // namespace khz::test
