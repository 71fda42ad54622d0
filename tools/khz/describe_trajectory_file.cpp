// `khz info` for device trajectories (CSV), the one CSV kind khz info reads.
#include "describe_files.hpp"

#include <khz/haptic/device/trajectory_file.hpp>

#include <filesystem>
#include <iostream>
#include <vector>

namespace khz::tool {

void describe_trajectory_file(const std::string& file) {
  std::vector<haptic::TrajectorySample> samples;
  try {
    samples = haptic::read_trajectory(file);
  } catch (const reduced::ParseError& error) {
    throw reduced::Error(
        file + " is not a device trajectory, the only CSV khz info reads: " + error.what());
  }
  Eigen::AlignedBox3d positions;
  for (const haptic::TrajectorySample& sample : samples) positions.extend(sample.pose.position);
  info_line("kind") << "device trajectory (CSV)\n";
  info_line("samples") << samples.size() << "\n";
  info_line("duration") << samples.back().time - samples.front().time
                        << " s (t = " << samples.front().time << " .. " << samples.back().time
                        << " s)\n";
  info_line("positions") << box_text(positions) << " m\n";
  describe_file_size(std::filesystem::file_size(file));
}

}  // namespace khz::tool
