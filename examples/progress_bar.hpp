#pragma once
// A text progress bar for the examples: one line per stage, redrawn in place.

#include <khz/reduced/progress.hpp>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <string>

namespace khz::examples {

/// A ProgressCallback that draws "  stage [#####     ] done/total" and never cancels.
inline bool print_progress(const khz::reduced::Progress& progress) {
  constexpr int width = 30;
  const auto filled = static_cast<int>(std::lround(progress.fraction() * width));
  std::cout << "\r  " << std::left << std::setw(22) << progress.stage << " ["
            << std::string(static_cast<std::size_t>(filled), '#')
            << std::string(static_cast<std::size_t>(width - filled), ' ') << "] " << progress.done
            << "/" << progress.total << std::flush;
  if (progress.done == progress.total) std::cout << "\n";
  return true;
}

}  // namespace khz::examples
