#pragma once
// What the viewer writes over the scene: the loop's and the drawing's rates, each hand's contact
// wrench and counters, and the keys and mouse buttons.

#include <khz/haptic/world/cycle_record.hpp>

#include <span>
#include <string>
#include <vector>

namespace khz::viewer {

/// The rates the overlay reports, measured by the viewer over its last half second or so.
struct OverlayRates {
  double cycles_per_second = 0.0;       ///< Haptic cycles run per second of wall time.
  double microseconds_per_cycle = 0.0;  ///< Mean work per cycle (µs, LoopStatistics::mean_work).
  double frames_per_second = 0.0;       ///< Frames drawn per second of wall time.
};

/// The status lines: first the rates, then for each hand (in `records`' order, named by the
/// same entry of `hand_names`, e.g. "peg, mouse") its contact force and torque on the held
/// object (magnitudes, N and N m, about the grasp point) and, on a second line, the points in
/// contact and the deepest tree level its queries rendered (haptic::CycleRecord::contact:
/// summed over the hand's pairs; "cut short" when graceful degradation stopped before a level
/// contact reached), or that the cycle had no valid query. Plain ASCII: the overlay's font
/// (stb_easy_font) has no other characters. Pure; no display needed.
/// @param hand_names one per record; a missing name leaves the parentheses out.
std::vector<std::string> overlay_status(const OverlayRates& rates,
                                        std::span<const haptic::CycleRecord> records,
                                        std::span<const std::string> hand_names);

/// The keys and mouse buttons, one short line each group (ASCII).
std::vector<std::string> overlay_help();

}  // namespace khz::viewer
