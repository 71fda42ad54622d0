#pragma once
// Whole-file reads and writes with IoError messages that name the file.

#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace khz::reduced::detail {

/// Reads the whole file. @throws IoError if it cannot be opened or read.
std::string read_file_bytes(const std::filesystem::path& file);
/// Replaces the file's content with `bytes`. @throws IoError if it cannot be written.
void write_file_bytes(const std::filesystem::path& file, std::string_view bytes);
/// Replaces the file's content with `bytes` atomically: writes a temporary file in the same
/// directory, flushes it to disk and renames it over `file`, so readers (and a crash at any
/// point) see either the old content or the new, never part of it. A new file gets the
/// permissions 0666 minus the umask, an existing one is replaced by a new inode.
/// @throws IoError naming `file` and the system's reason; the temporary file is removed.
void replace_file_bytes(const std::filesystem::path& file, std::string_view bytes);
/// The same with the content given in pieces, written one after the other (no copy joins them).
void replace_file_bytes(const std::filesystem::path& file,
                        std::span<const std::string_view> pieces);

}  // namespace khz::reduced::detail
