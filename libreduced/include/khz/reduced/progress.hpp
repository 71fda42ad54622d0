#pragma once
// Progress reporting and cancellation for precomputations that can take seconds or more.

#include <khz/reduced/export.hpp>

#include <cstdint>
#include <functional>
#include <string_view>

namespace khz::reduced {

/// One progress report: `done` of `total` units of the named stage are finished.
struct Progress {
  /// What is running, e.g. "linear modes" or "modal derivatives"; valid during the call only.
  std::string_view stage;
  std::int64_t done = 0;  ///< Units finished, 0 ≤ done ≤ total.
  /// Units in the stage (≥ 1). Iterative stages (e.g. "linear modes") start from an estimate
  /// and raise it if the work runs longer, so their fraction() can dip; `done` never decreases.
  std::int64_t total = 0;

  /// done / total in [0, 1].
  double fraction() const noexcept {
    return total > 0 ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
  }
};

/// Called from the computing thread at the start of each stage (done = 0), after each unit of
/// work, and at its end (done = total); reports of one stage never go backwards. Return true
/// to continue, false to cancel: the computation then throws Cancelled at its next check,
/// within one unit of work. An empty callback reports nothing and never cancels. Exceptions the
/// callback throws propagate to the caller of the computation.
using ProgressCallback = std::function<bool(const Progress&)>;

}  // namespace khz::reduced
