#pragma once
// Whole-file reads and writes with IoError messages that name the file.

#include <filesystem>
#include <string>
#include <string_view>

namespace khz::reduced::detail {

/// Reads the whole file. @throws IoError if it cannot be opened or read.
std::string read_file_bytes(const std::filesystem::path& file);
/// Replaces the file's content with `bytes`. @throws IoError if it cannot be written.
void write_file_bytes(const std::filesystem::path& file, std::string_view bytes);

}  // namespace khz::reduced::detail
