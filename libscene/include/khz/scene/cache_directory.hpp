#pragma once
// Where prepared products are kept unless the user says otherwise.

#include <filesystem>
#include <khz/scene/export.hpp>

namespace khz::scene {

/// The default product cache directory of `khz prep` and `khz run`: $XDG_CACHE_HOME/kilohertz
/// when XDG_CACHE_HOME is an absolute path (the XDG base directory rule), otherwise
/// $HOME/.cache/kilohertz when HOME is set and absolute. One cache for every scene: products are
/// named by content, so scenes that share an object's inputs share its products, and scene
/// directories (the examples in a source tree, read-only installs) stay untouched. Empty when
/// neither variable helps; the caller then chooses (`khz prep` uses `.khz-cache` beside the
/// scene file).
KHZ_SCENE_API std::filesystem::path default_cache_directory();

}  // namespace khz::scene
