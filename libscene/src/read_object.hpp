#pragma once
// Reading one entry of a scene's "objects" array.

#include "read_common.hpp"

#include <khz/scene/object_description.hpp>

namespace khz::scene::detail {

/// Reads and checks objects[i] on its own (names across objects and roles against the held
/// object are checked by the scene).
/// @throws SceneError at the first problem.
ObjectDescription read_object(const Json& value, const Location& at, const ReadContext& context);

}  // namespace khz::scene::detail
