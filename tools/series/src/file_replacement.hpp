#pragma once
// Files written whole through a temporary file renamed over the target.

#include <filesystem>
#include <functional>
#include <ostream>

namespace khz::series::detail {

/// Has `write` write the new content of `file` to a stream on a temporary file in the same
/// directory, then renames it over `file`: a reader sees the old content or the new, never
/// part of it. Not flushed to disk (fsync): after a system crash the newest content may be
/// lost, never mixed with the old.
/// @throws reduced::IoError naming `file` and the system's reason if the temporary file
///         cannot be created, written or renamed; what `write` throws. The temporary file is
///         removed on any failure.
void replace_file(const std::filesystem::path& file,
                  const std::function<void(std::ostream& out)>& write);

}  // namespace khz::series::detail
