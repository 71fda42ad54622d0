#pragma once
// Line- and token-oriented reading of text mesh formats with precise error locations.

#include <khz/reduced/errors.hpp>

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>

namespace khz::reduced::detail {

/// Comment character for formats without comments: a NUL never starts a line of a text file.
inline constexpr char no_comment = '\0';
/// Vertex and node indices are int: the most vertices, nodes or group ids a mesh can have.
inline constexpr std::int64_t max_index = std::numeric_limits<int>::max();
/// Bounds for integers whose range the caller checks itself, with a message naming their role.
inline constexpr std::int64_t any_integer_min = std::numeric_limits<std::int64_t>::min();
inline constexpr std::int64_t any_integer_max = std::numeric_limits<std::int64_t>::max();

/// Walks a text buffer line by line and splits lines into whitespace-separated tokens.
/// Every failure throws ParseError naming the source and the current 1-based line.
/// Numbers are parsed with std::from_chars: locale-independent, no allocation.
class TextScanner {
 public:
  TextScanner(std::string_view data, std::string source);

  /// Advances to the next line (without its terminator, '\r' stripped). False at end of data.
  bool next_line();
  /// Advances to the next line that is not blank and does not start with `comment` (after
  /// leading whitespace). False at end of data.
  bool next_content_line(char comment);
  /// Like next_content_line(), but a missing line is a "truncated file" error saying `expected`.
  void require_content_line(char comment, std::string_view expected);
  /// Moves to the line of `item` number `index` (0-based) of the `count` a header declared; at
  /// the end of data fails with "file ends early: expected <item> <index+1> of <count>".
  void require_row(char comment, std::string_view item, std::int64_t index, std::int64_t count);

  /// Next token of the current line, or an empty view when the line is exhausted.
  std::string_view next_token();
  /// Next token; a missing one is an error saying `expected`.
  std::string_view require_token(std::string_view expected);
  /// The unread rest of the current line, leading whitespace skipped.
  std::string_view rest_of_line();
  /// True when only whitespace remains on the current line.
  bool line_exhausted();

  /// Next token as a finite double; `what` names the value in error messages.
  double require_double(std::string_view what);
  /// Next token as an integer in [min, max].
  std::int64_t require_integer(std::string_view what, std::int64_t min, std::int64_t max);

  std::int64_t line_number() const noexcept { return m_line_number; }
  /// Bytes not yet consumed by next_line(): an upper bound for what the rest can hold.
  std::size_t remaining_bytes() const noexcept { return m_data.size() - m_next; }
  const std::string& source() const noexcept { return m_source; }

  /// Throws ParseError at the current line.
  [[noreturn]] void fail(const std::string& message) const;

 private:
  std::string_view m_data;
  std::string m_source;
  std::size_t m_next = 0;  // offset of the first byte after the current line
  std::int64_t m_line_number = 0;
  std::string_view m_line;  // unread part of the current line
};

/// `token` for an error message: quoted, shortened, with control bytes shown as '?'.
std::string quoted_token(std::string_view token);

/// Parses all of `token` as a finite double, or returns false.
bool parse_double(std::string_view token, double& value) noexcept;
/// Parses all of `token` as a decimal integer, or returns false.
bool parse_integer(std::string_view token, std::int64_t& value) noexcept;

/// "<what> <value> is outside [<min>, <max>]": the message of every integer range check.
std::string outside_range(std::string_view what, std::string_view value, std::int64_t min,
                          std::int64_t max);

/// Rejects a header count that cannot fit: `count` items of at least `min_bytes_each` bytes in
/// what `at` has left. Stops hostile headers from driving huge allocations. `at` is a
/// TextScanner or a binary reader: anything with remaining_bytes() and fail().
template <typename Reporter>
void check_count_fits(const Reporter& at, std::int64_t count, std::size_t min_bytes_each,
                      std::string_view what) {
  if (count < 0) at.fail("negative " + std::string(what) + " count " + std::to_string(count));
  const std::size_t room = at.remaining_bytes() / min_bytes_each;
  if (static_cast<std::uint64_t>(count) > room) {
    at.fail("header declares " + std::to_string(count) + " " + std::string(what) +
            " but the rest of the file can hold at most " + std::to_string(room));
  }
}

}  // namespace khz::reduced::detail
