#include "scene_preparation.hpp"

#include "progress_bar.hpp"

#include <khz/scene/cache_directory.hpp>
#include <khz/scene/prepare_scene.hpp>

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <vector>

namespace khz::tool {
namespace {

volatile std::sig_atomic_t interrupted = 0;

void on_interrupt(int) {
  interrupted = 1;
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process at once
}

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", seconds);
  return text;
}

}  // namespace

InterruptRequest::InterruptRequest() : m_previous(std::signal(SIGINT, on_interrupt)) {
  interrupted = 0;
}

InterruptRequest::~InterruptRequest() { std::signal(SIGINT, m_previous); }

bool InterruptRequest::requested() const noexcept { return interrupted != 0; }

std::filesystem::path cache_directory(const std::string& option, const std::string& scene_file) {
  if (!option.empty()) return option;
  std::filesystem::path directory = scene::default_cache_directory();
  if (directory.empty()) {
    directory = std::filesystem::absolute(scene_file).parent_path() / ".khz-cache";
  }
  return directory;
}

void print_prepare_summary(std::ostream& out, const scene::PreparedScene& prepared,
                           const std::filesystem::path& cache) {
  std::vector<std::vector<std::string>> rows{{"object", "product", "how", "seconds", "file"}};
  for (const scene::PrepareRecord& record : prepared.records) {
    std::string how(scene::origin_name(record.origin));
    if (record.rank >= 0) how += " (rank " + std::to_string(record.rank) + ")";
    rows.push_back({record.object, std::string(scene::step_name(record.step)), how,
                    seconds_text(record.seconds), record.file.filename().string()});
  }
  std::vector<std::size_t> widths(rows.front().size(), 0);
  for (const auto& row : rows) {
    for (std::size_t c = 0; c < row.size(); ++c) widths[c] = std::max(widths[c], row[c].size());
  }
  out << "cache: " << cache.string() << "\n";
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t c = 0; c < row.size(); ++c) {
      const std::string padding(widths[c] - row[c].size(), ' ');
      line += c == 3 ? padding + row[c] : row[c] + padding;  // seconds right-aligned
      if (c + 1 < row.size()) line += "  ";
    }
    line.erase(line.find_last_not_of(' ') + 1);
    out << "  " << line << "\n";
  }
  using Origin = scene::PrepareRecord::Origin;
  out << "total: " << seconds_text(prepared.total_seconds()) << " s ("
      << prepared.count(Origin::computed) << " computed, " << prepared.count(Origin::read)
      << " read, " << prepared.count(Origin::built) << " built)\n";
  for (const scene::PrepareRecord& record : prepared.records) {
    if (record.note.empty()) continue;
    out << "note: " << record.object << " " << scene::step_name(record.step) << ": " << record.note
        << "\n";
  }
  for (const scene::PrepareWarning& warning : prepared.warnings) {
    out << "warning: object \"" << warning.object << "\": " << warning.message << "\n";
  }
}

scene::PreparedScene prepare_with_progress(const scene::SceneDescription& description,
                                           const std::filesystem::path& cache,
                                           std::ostream& summary, reduced::WorkGroup* group) {
  scene::ProductCache products(cache);
  const bool shows = !group || group->rank() == 0;
  ProgressBar bar(std::cerr, shows && ::isatty(STDERR_FILENO) == 1);
  const InterruptRequest interrupt;
  scene::PrepareOptions options;
  options.group = group;
  options.progress = [&](const std::string& object, scene::PrepareStep step,
                         const reduced::Progress& progress) {
    if (shows) bar.update(object + " " + std::string(scene::step_name(step)), progress);
    return !interrupt.requested();
  };
  scene::PreparedScene prepared = scene::prepare_scene(description, products, options);
  bar.clear();
  if (shows) print_prepare_summary(summary, prepared, products.directory());
  return prepared;
}

}  // namespace khz::tool
