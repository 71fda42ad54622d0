// The C++ in the docs is code that builds and runs: every ```cpp block of docs/*.md and README.md
// names, on the line before it, the program it is taken from (<!-- program: examples/X.cpp -->),
// that program is built by examples/CMakeLists.txt (and run by CTest, tests/CMakeLists.txt), and
// every line of the block is a line of the program (blanks aside). A block may leave lines of
// the program out (and mark the gap with a line "// …"), but it cannot say anything the program
// does not.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

const std::filesystem::path source_dir = KHZ_SOURCE_DIR;

std::string read_text(const std::filesystem::path& file) {
  std::ifstream stream(file);
  std::stringstream text;
  text << stream.rdbuf();
  return text.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) lines.push_back(line);
  return lines;
}

/// The line without leading and trailing blanks and with inner runs of blanks as one space (so
/// that clang-format's alignment of trailing comments does not matter).
std::string trimmed(const std::string& line) {
  std::string result;
  for (const char c : line) {
    const bool blank = c == ' ' || c == '\t';
    if (blank && (result.empty() || result.back() == ' ')) continue;
    result += blank ? ' ' : c;
  }
  if (!result.empty() && result.back() == ' ') result.pop_back();
  return result;
}

/// A ```cpp block: where it is and which program it says it comes from.
struct Block {
  std::filesystem::path document;
  int line = 0;  // of the opening fence, 1-based
  std::string program;
  std::vector<std::string> lines;
};

std::vector<Block> cpp_blocks(const std::filesystem::path& document) {
  const std::vector<std::string> lines = lines_of(read_text(document));
  std::vector<Block> blocks;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (trimmed(lines[i]) != "```cpp") continue;
    Block block{document, static_cast<int>(i + 1), {}, {}};
    const std::string marker = "<!-- program: ";
    for (std::size_t before = i; before-- > 0;) {
      const std::string text = trimmed(lines[before]);
      if (text.empty()) continue;
      if (text.rfind(marker, 0) == 0 && text.size() > marker.size() + 4) {
        block.program = text.substr(marker.size(), text.size() - marker.size() - 4);
      }
      break;
    }
    for (++i; i < lines.size() && trimmed(lines[i]) != "```"; ++i) {
      block.lines.push_back(lines[i]);
    }
    blocks.push_back(block);
  }
  return blocks;
}

std::vector<std::filesystem::path> documents() {
  std::vector<std::filesystem::path> files{source_dir / "README.md"};
  for (const auto& entry : std::filesystem::directory_iterator(source_dir / "docs")) {
    if (entry.path().extension() == ".md") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

/// The first line of `block` (not blank, not an elision "// …") that is not a line of
/// `program`, or empty if every one is.
std::string first_line_not_in(const Block& block, const std::vector<std::string>& program) {
  std::vector<std::string> known;
  for (const std::string& line : program) known.push_back(trimmed(line));
  std::sort(known.begin(), known.end());
  for (const std::string& raw : block.lines) {
    const std::string line = trimmed(raw);
    if (line.empty() || line == "// …") continue;
    if (!std::binary_search(known.begin(), known.end(), line)) return line;
  }
  return {};
}

TEST(DocSnippets, EveryCppBlockIsTakenFromABuiltProgram) {
  const std::string examples_cmake = read_text(source_dir / "examples" / "CMakeLists.txt");
  int blocks = 0;
  for (const std::filesystem::path& document : documents()) {
    for (const Block& block : cpp_blocks(document)) {
      ++blocks;
      const std::string where = document.filename().string() + ":" + std::to_string(block.line);
      ASSERT_FALSE(block.program.empty())
          << where << ": a ```cpp block needs <!-- program: examples/X.cpp --> before it";
      const std::filesystem::path program = source_dir / block.program;
      ASSERT_TRUE(std::filesystem::is_regular_file(program)) << where << ": " << block.program;
      // Built: its name (without .cpp) is a target or an item of a target list there.
      const std::string name = program.stem().string();
      EXPECT_NE(examples_cmake.find(" " + name), std::string::npos)
          << where << ": examples/CMakeLists.txt does not build " << name;
      EXPECT_EQ(first_line_not_in(block, lines_of(read_text(program))), "")
          << where << ": this line is not in " << block.program;
    }
  }
  EXPECT_GE(blocks, 8) << "the docs' C++ blocks were not found";
}

// The check itself: a line the program does not have is reported, whatever its blanks.
TEST(DocSnippets, ALineTheProgramDoesNotHaveIsFound) {
  const std::vector<std::string> program{"int a = 1;", "  int b = 2;  // two", "return a + b;"};
  Block block;
  block.lines = {"int a = 1;", "// …", "  return a + b;", "int b = 2; // two"};
  EXPECT_EQ(first_line_not_in(block, program), "");
  block.lines = {"int a = 1;", "int a = 2;"};
  EXPECT_EQ(first_line_not_in(block, program), "int a = 2;");
}

}  // namespace
