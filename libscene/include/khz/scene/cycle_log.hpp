#pragma once
// What `khz run` records per haptic cycle, and its CSV file (read back by `khz report` and
// `khz info`).

#include <khz/haptic/world/cycle_record.hpp>
#include <khz/scene/export.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace khz::scene {

/// One haptic cycle as logged. Forces are world axes; the torque is about the held object's
/// grasp point.
struct KHZ_SCENE_API CycleRow {
  double time = 0.0;                                 ///< s, the cycle's start.
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< Contact force on the held object (N).
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< Contact torque (N·m).
  Eigen::Vector3d rendered_force = Eigen::Vector3d::Zero();   ///< What the device got (N).
  Eigen::Vector3d rendered_torque = Eigen::Vector3d::Zero();  ///< (N·m).
  std::int64_t nodes = 0;                                     ///< Tree nodes traversed, all pairs.
  std::int64_t skipped = 0;                                   ///< Nodes temporal coherence skipped.
  std::int64_t contacts = 0;                                  ///< Points in contact.
  int level = -1;                                             ///< Deepest tree level rendered.
  bool complete = true;   ///< No level was cut by graceful degradation.
  double query_us = 0.0;  ///< Contact queries (µs, steady clock).
  double cycle_us = 0.0;  ///< The whole cycle (µs): device, query, coupling, time steps.
  Eigen::Vector3d manipulandum = Eigen::Vector3d::Zero();  ///< Device grasp point, world (m).
  Eigen::Vector3d simulation = Eigen::Vector3d::Zero();    ///< Held object's grasp point (m).
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< Held object's.
  bool ok = true;                   ///< Device read, query, coupling and every time step succeeded.
  double penetration = 0.0;         ///< Deepest point in contact (m; ContactStatistics).
  double penetration_voxels = 0.0;  ///< The same in voxels (CycleRecord::penetration_voxels).
  double residual_force = 0.0;      ///< |F_contact + F_VC| at the queried pose (N).
  double energy = 0.0;              ///< The passivity observer after the cycle (J, device).
  /// Of the points in contact, those whose friction slid (ContactStatistics::points_sliding).
  std::int64_t sliding = 0;

  /// The row of a cycle's record, with the cycle's measured cost.
  static CycleRow from(const haptic::CycleRecord& record, double cycle_us) noexcept;
};

/// The CSV header line `khz run` writes (without newline): time, force_x … torque_z,
/// rendered_force_x … rendered_torque_z, nodes, skipped, contacts, level, complete, query_us,
/// cycle_us, manipulandum_x … z, simulation_x … z, orientation_w, _x, _y, _z, ok, penetration,
/// penetration_voxels, residual_force, energy, sliding.
KHZ_SCENE_API std::string cycle_csv_header();

/// Whether `line` is the header of a cycle log read_cycle_csv() reads: cycle_csv_header(), or
/// that of an earlier version without the last column (sliding: 0 when read) or the last five.
KHZ_SCENE_API bool is_cycle_csv_header(const std::string& line);

/// Writes the rows as CSV (header first; each number as the shortest text that reads back to
/// the same double, so read_cycle_csv() returns the rows exactly).
/// @throws reduced::IoError naming the file if it cannot be written.
KHZ_SCENE_API void write_cycle_csv(const std::vector<CycleRow>& rows,
                                   const std::filesystem::path& file);

/// Reads a file write_cycle_csv() wrote.
/// Logs of earlier versions, without the last four columns, read with those fields zero.
/// @throws reduced::IoError if it cannot be read; reduced::ParseError (file:line) if the
///         header is not cycle_csv_header() (or the earlier one) or a row does not have its
///         columns as numbers.
KHZ_SCENE_API std::vector<CycleRow> read_cycle_csv(const std::filesystem::path& file);

/// read_cycle_csv() on text in memory; `source` names it in messages (for fuzzers and tests).
/// @throws reduced::ParseError as read_cycle_csv().
KHZ_SCENE_API std::vector<CycleRow> parse_cycle_csv(std::string_view data,
                                                    const std::string& source);

}  // namespace khz::scene
