#pragma once
// What the viewer says on stderr while it prepares a scene: which products it computes and
// which it reads from the product cache.

#include <khz/reduced/progress.hpp>
#include <khz/scene/prepared_scene.hpp>

#include <string>
#include <string_view>

namespace khz::viewer {

/// The stage scene::prepare_scene() reports first, as one unit, for every product it reads
/// from the cache instead of computing (its fetch wraps the read in a reduced::StageProgress of
/// this name); computations report their own stages. test_tools_viewer_preparation checks this
/// against real preparations, so a rename in libscene fails there rather than silently turning
/// every "cached" back into "preparing".
inline constexpr std::string_view cache_read_stage = "reading";

/// One line per product, chosen from the first progress report of each: scene::PrepareOptions'
/// progress callback passes every report to line(); the viewer prints what comes back unless
/// it is empty. Pure; no display needed.
class PreparationMessages {
 public:
  /// For the first report of a product (a new object or step): "<object> <step>: cached" when
  /// its stage is cache_read_stage, "preparing <object> <step> ..." otherwise (computed, or
  /// built anew as every preparation does for some products). Empty for later reports of the
  /// same product.
  std::string line(const std::string& object, scene::PrepareStep step,
                   const reduced::Progress& progress);

 private:
  std::string m_object;
  int m_step = -1;  // of the product last announced; −1 before any
};

/// After the preparation, from its records: "prepared in S s: N cached, M computed, K built"
/// (read from the cache, computed and stored, computed and never cached).
std::string preparation_summary(const scene::PreparedScene& prepared);

}  // namespace khz::viewer
