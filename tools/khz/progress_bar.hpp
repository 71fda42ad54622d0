#pragma once
// Progress of long computations on a terminal: one line redrawn in place with a bar, the
// percentage and the estimated time left; on anything else (a log file, CI), one line per
// finished stage with its time.

#include <khz/reduced/progress.hpp>

#include <chrono>
#include <iosfwd>
#include <string>
#include <string_view>

namespace khz::tool {

/// Draws reduced::Progress reports of one computation after another. Not thread-safe: call it
/// from the computing thread (where ProgressCallbacks run).
class ProgressBar {
 public:
  /// @param out where to draw (the tool uses std::cerr, so stdout stays for results).
  /// @param interactive true for a terminal: redraw one line in place (carriage return and
  ///        ANSI erase-to-end-of-line); false: print a line as each stage finishes.
  ProgressBar(std::ostream& out, bool interactive);
  /// Erases the line (clear()): on an error too, its message then starts on a clean line.
  ~ProgressBar() { clear(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Shows `progress` of the computation named `label` (e.g. "dino distance_field"). A report
  /// with done = 0, or of another label or stage, starts a new stage and its clock; the time
  /// left is estimated from the stage's rate so far, once it has run for a second.
  void update(std::string_view label, const reduced::Progress& progress);

  /// Erases the line being redrawn (interactive), so that what follows starts on a clean line.
  void clear();

 private:
  using Clock = std::chrono::steady_clock;

  void draw(std::string_view label, const reduced::Progress& progress, Clock::time_point now);

  std::ostream& m_out;
  bool m_interactive;
  std::string m_stage;  // label and stage of the stage being shown
  Clock::time_point m_start;
  Clock::time_point m_drawn;
  bool m_finish_shown = false;  // the current stage's end was printed (not interactive)
  bool m_line_open = false;
};

}  // namespace khz::tool
