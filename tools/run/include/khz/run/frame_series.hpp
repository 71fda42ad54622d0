#pragma once
// A run as a ParaView time series: per frame, every object's surface, the contact pairs' points
// with their state and the contact force, listed in one .pvd collection.

#include <khz/run/frame_content.hpp>
#include <khz/series/pvd_collection.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace khz::run {

/// Writes frames to `<directory>/run.pvd` and `<directory>/run/`: per frame, one part per
/// object named after it (its surface in the world, .vtp), one part per contact pair
/// "points_<pointshell object>" (the points on the rendered levels, point data "state": 0
/// untouched, 1 looked at, 2 in contact), and the part "force" (one point at the grasp point with
/// the vector "force", N: show it with ParaView's Glyph filter).
class FrameSeries {
 public:
  /// @throws reduced::IoError if the directory or collection cannot be written.
  FrameSeries(const scene::SceneRuntime& runtime, const std::filesystem::path& directory);

  /// Adds one time step. @throws reduced::IoError naming a file that cannot be written;
  /// reduced::Error if the frame's time is not later than the previous one.
  void write(const FrameContent& frame);

  const std::filesystem::path& collection_file() const noexcept { return m_collection.file(); }

 private:
  series::PvdCollection m_collection;
  std::vector<std::string> m_object_names;
  std::vector<std::string> m_point_parts;
  std::vector<reduced::TriangleMatrix> m_triangles;
};

}  // namespace khz::run
