#include <khz/reduced/errors.hpp>
#include <khz/scene/product_cache.hpp>

#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <string>

namespace khz::scene {
namespace {

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
void write_text(const std::string& text, const std::filesystem::path& file) {
  std::ofstream(file) << text;
}

TEST(ProductCache, ComputesOnceThenReadsByKeyAndRecomputesForANewKey) {
  ProductCache cache(test::scratch_directory("keys"));
  int computations = 0;
  const auto compute = [&] {
    ++computations;
    return std::string("field ") + std::to_string(computations);
  };
  const auto fetch = [&](const std::string& key) {
    return cache.fetch<std::string>("dino field", key, "txt", read_text, compute, write_text);
  };
  EXPECT_EQ(fetch("aa11"), "field 1");
  EXPECT_EQ(fetch("aa11"), "field 1");  // read back, not computed again
  EXPECT_EQ(fetch("bb22"), "field 2");  // another key: another product
  EXPECT_EQ(computations, 2);
  ASSERT_EQ(cache.records().size(), 3U);
  EXPECT_TRUE(cache.records()[0].computed);
  EXPECT_FALSE(cache.records()[1].computed);
  EXPECT_TRUE(cache.records()[2].computed);
  EXPECT_EQ(cache.computed_count(), 2);
  EXPECT_EQ(cache.records()[1].file.filename(), "dino_field-aa11.txt");

  // A second cache on the same directory (the next `khz prep`) computes nothing.
  ProductCache again(cache.directory());
  EXPECT_EQ(again.fetch<std::string>("dino field", "bb22", "txt", read_text, compute, write_text),
            "field 2");
  EXPECT_EQ(again.computed_count(), 0);
}

TEST(ProductCache, AFailedComputationOrWriteLeavesNoFile) {
  ProductCache cache(test::scratch_directory("failures"));
  const auto throwing_compute = []() -> std::string { throw std::runtime_error("cancelled"); };
  EXPECT_THROW(cache.fetch<std::string>("a", "k", "txt", read_text, throwing_compute, write_text),
               std::runtime_error);
  const auto half_write = [](const std::string& text, const std::filesystem::path& file) {
    write_text(text.substr(0, 2), file);
    throw reduced::IoError("disk full");
  };
  EXPECT_THROW(cache.fetch<std::string>(
                   "a", "k", "txt", read_text, [] { return std::string("product"); }, half_write),
               reduced::IoError);
  EXPECT_TRUE(std::filesystem::is_empty(cache.directory()));
  EXPECT_TRUE(cache.records().empty());
}

TEST(ProductCache, NamesAreMadeSafeForPathsAndBadDirectoriesAreReported) {
  ProductCache cache(test::scratch_directory("names"));
  EXPECT_EQ(cache.file("../dragon field", "k", "khzsdf").filename(), "___dragon_field-k.khzsdf");
  EXPECT_EQ(cache.file("../dragon field", "k", "khzsdf").parent_path(), cache.directory());
  const std::filesystem::path blocked = cache.directory() / "a-file";
  write_text("not a directory", blocked);
  try {
    ProductCache bad(blocked / "cache");
    ADD_FAILURE() << "no error";
  } catch (const reduced::IoError& error) {
    EXPECT_NE(std::string(error.what()).find((blocked / "cache").string()), std::string::npos);
  }
}

/// The id of a process that has ended (a child that exited and was reaped).
pid_t ended_process() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

TEST(ProductCache, TemporariesOfDeadProcessesOfThisHostAreRemovedOnOpening) {
  const std::filesystem::path directory = test::scratch_directory("abandoned");
  const std::filesystem::path live_target = ProductCache(directory).file("field", "k1", "txt");
  // The name a temporary gets: the writer's temporary while it writes.
  std::filesystem::path live_temporary;
  ProductCache(directory).fetch<std::string>(
      "field", "k1", "txt", read_text, [] { return std::string("product"); },
      [&](const std::string& text, const std::filesystem::path& file) {
        live_temporary = file;
        write_text(text, file);
      });
  ASSERT_FALSE(live_temporary.empty());
  const std::string marker = live_temporary.filename().string();
  const std::string prefix = marker.substr(0, marker.rfind('-') + 1);  // "<file>.partial-<host>-"
  ASSERT_NE(prefix.find(".partial-"), std::string::npos) << marker;
  EXPECT_EQ(marker.substr(prefix.size()), std::to_string(::getpid()));

  const std::string dead = directory / (prefix + std::to_string(ended_process()));
  const std::string alive = directory / (prefix + std::to_string(::getpid()));
  const std::string other_host = directory / "field-k2.txt.partial-elsewhere-1";
  for (const std::string& file : {dead, alive, other_host}) write_text("half a product", file);
  const ProductCache reopened(directory);
  EXPECT_FALSE(std::filesystem::exists(dead));        // its writer died: removed
  EXPECT_TRUE(std::filesystem::exists(alive));        // still being written
  EXPECT_TRUE(std::filesystem::exists(other_host));   // not this host's to judge
  EXPECT_TRUE(std::filesystem::exists(live_target));  // products are never touched
}

}  // namespace
}  // namespace khz::scene
