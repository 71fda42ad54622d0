#include <khz/test/data_paths.hpp>
#include <khz/test/fixtures.hpp>

#include <fstream>
#include <set>
#include <sstream>

namespace khz::test {

std::filesystem::path cgal_mesh(std::string_view name) {
  std::filesystem::path path = std::filesystem::path(cgal_mesh_dir) / name;
  if (!std::filesystem::exists(path)) {
    throw reduced::IoError(path.string() + ": CGAL demo mesh missing (install libcgal-demo)");
  }
  return path;
}

std::filesystem::path test_file(std::string_view relative) {
  std::filesystem::path path = std::filesystem::path(test_data_dir) / relative;
  if (!std::filesystem::exists(path)) throw reduced::IoError(path.string() + ": test file missing");
  return path;
}

namespace {

/// The running test's own scratch directory, created if missing.
std::filesystem::path test_scratch_directory() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir = std::filesystem::path(scratch_dir);
  if (info != nullptr) dir /= std::string(info->test_suite_name()) + "." + info->name();
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

std::filesystem::path scratch_file(std::string_view name) {
  std::filesystem::path path = test_scratch_directory() / name;
  std::filesystem::remove(path);
  return path;
}

std::filesystem::path scratch_directory(std::string_view name) {
  std::filesystem::path directory = test_scratch_directory() / name;
  std::filesystem::remove_all(directory);
  return directory;
}

std::string read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw reduced::IoError(file.string() + ": cannot open");
  std::ostringstream content;
  content << in.rdbuf();
  return content.str();
}

void expect_corpus_rejected(std::string_view folder, std::span<const MalformedFile> cases,
                            const std::function<void(const std::filesystem::path&)>& parse) {
  std::set<std::string> covered;
  for (const MalformedFile& c : cases) {
    SCOPED_TRACE(c.file);
    covered.insert(c.file);
    const std::filesystem::path file = test_file(std::string(folder) + "/" + c.file);
    EXPECT_TRUE(throws_with_message([&] { parse(file); }, c.message));
  }
  for (const auto& entry : std::filesystem::directory_iterator(test_file(folder))) {
    EXPECT_TRUE(covered.contains(entry.path().filename().string()))
        << entry.path() << " has no expected message";
  }
}

}  // namespace khz::test
