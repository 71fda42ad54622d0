// `khz info` for CSV files: a `khz run` cycle log (recognised by its header) or a device
// trajectory.
#include "describe_files.hpp"

#include <khz/scene/cycle_log.hpp>
#include <khz/scene/run_summary.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace khz::tool {
namespace {

void describe_cycle_log(const std::string& file) {
  const std::vector<scene::CycleRow> rows = scene::read_cycle_csv(file);
  const double period = rows.size() > 1 ? rows[1].time - rows[0].time : 0.0;
  const scene::RunSummary s = scene::summarize(rows, period);
  info_line("kind") << "khz run cycle log (CSV)\n";
  info_line("cycles") << s.cycles << " (" << s.duration << " s at "
                      << (period > 0.0 ? 1.0 / period : 0.0) << " Hz), " << s.cycles_in_contact
                      << " in contact\n";
  info_line("us per cycle") << "mean " << s.cycle_us.mean << ", p99 " << s.cycle_us.p99 << ", max "
                            << s.cycle_us.max << "\n";
  info_line("us per query") << "mean " << s.query_us.mean << ", p99 " << s.query_us.p99 << ", max "
                            << s.query_us.max << "\n";
  info_line("contact") << "max " << s.max_contacts << " points, max " << s.max_nodes
                       << " nodes, deepest level " << s.deepest_level << "\n";
  info_line("forces") << "max " << s.max_force << " N contact, " << s.max_rendered_force
                      << " N rendered\n";
  info_line("failed cycles") << s.failed_cycles << (s.finite ? "" : " (non-finite values)") << "\n";
  describe_file_size(std::filesystem::file_size(file));
}

}  // namespace

void describe_csv_file(const std::string& file) {
  std::ifstream stream(file);
  std::string header;
  std::getline(stream, header);
  if (scene::is_cycle_csv_header(header)) {
    describe_cycle_log(file);
  } else {
    describe_trajectory_file(file);
  }
}

}  // namespace khz::tool
