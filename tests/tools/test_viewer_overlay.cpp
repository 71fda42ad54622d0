// The interactive viewer's overlay text (khz_viewer_input), headless: the lines written over the
// scene for given rates and cycle records, and the help.
#include <khz/viewer/overlay_text.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace khz::viewer {
namespace {

haptic::CycleRecord touching() {
  haptic::CycleRecord record;
  record.contact_valid = true;
  record.contact.force = {3.0, 4.0, 0.0};      // 5 N
  record.contact.torque = {0.0, 0.0, -0.012};  // 0.012 N m
  record.contact.statistics.points_in_contact = 42;
  record.contact.statistics.deepest_level = 5;
  return record;
}

TEST(OverlayText, StatusGivesTheRatesAndEachHandsWrenchAndContact) {
  const OverlayRates rates{998.6, 12.34, 59.9};
  haptic::CycleRecord degraded = touching();
  degraded.contact.force = {0.0, 0.0, 0.25};
  degraded.contact.torque.setZero();
  degraded.contact.statistics.points_in_contact = 7;
  degraded.contact.statistics.points_sliding = 3;  // friction slid them
  degraded.contact.statistics.deepest_level = 2;
  degraded.contact.statistics.complete = false;
  const haptic::CycleRecord records[] = {touching(), degraded, haptic::CycleRecord{}};
  const std::string names[] = {"peg, mouse", "plate, scene's device", "tool, scene's device"};

  EXPECT_EQ(overlay_status(rates, records, names),
            (std::vector<std::string>{
                "haptic loop: 999 cycles/s, 12.3 us of work per cycle",
                "drawing: 60 frames/s",
                "hand 0 (peg, mouse): force 5 N, torque 0.012 N m",
                "  42 points in contact, deepest level 5",
                "hand 1 (plate, scene's device): force 0.25 N, torque 0 N m",
                "  7 points in contact (3 sliding), deepest level 2, cut short by degradation",
                "hand 2 (tool, scene's device): force 0 N, torque 0 N m",
                "  no contact query this cycle (none yet, or it refused its input)",
            }));
}

TEST(OverlayText, ForcesKeepThreeSignificantDigitsAndNamesAreOptional) {
  haptic::CycleRecord record = touching();
  record.contact.force = {0.0, -1234.5, 0.0};
  record.contact.torque = {2e-5, 0.0, 0.0};
  const std::vector<std::string> lines =
      overlay_status(OverlayRates{}, std::span(&record, 1), std::span<const std::string>());
  ASSERT_EQ(lines.size(), 4U);
  EXPECT_EQ(lines[0], "haptic loop: 0 cycles/s, 0.0 us of work per cycle");
  EXPECT_EQ(lines[2], "hand 0: force 1.23e+03 N, torque 2e-05 N m");
  EXPECT_TRUE(overlay_status(OverlayRates{}, {}, {}).size() == 2U);  // no hands: the rates only
}

TEST(OverlayText, EveryLineIsAsciiAndTheHelpNamesEveryControl) {
  const haptic::CycleRecord records[] = {touching()};
  const std::string names[] = {"peg, mouse"};
  std::vector<std::string> lines = overlay_status(OverlayRates{1000.0, 9.0, 60.0}, records, names);
  const std::vector<std::string> help = overlay_help();
  lines.insert(lines.end(), help.begin(), help.end());
  for (const std::string& line : lines) {
    for (const char c : line) {
      EXPECT_TRUE(c >= ' ' && c <= '~') << "not printable ASCII in: " << line;
    }
  }
  std::string all;
  for (const std::string& line : help) all += line + "\n";
  for (const char* control : {"left drag", "wheel", "right drag: orbit", "shift+wheel", "+/-: zoom",
                              "R: reset view", "Esc: quit"}) {
    EXPECT_NE(all.find(control), std::string::npos) << control;
  }
}

}  // namespace
}  // namespace khz::viewer
