#pragma once
// The parameters of one procedural shape spec ("peg:side=0.02,length=0.08") being read: each
// shape's reader asks for its parameters in order, with defaults and ranges, and the spec's
// canonical text is what it asked for, with the values used.

#include "json_reader.hpp"

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace khz::scene::detail {

/// "unknown <what> "<name>"; the <what>s are a, b, c" (`known` sorted), or with a close match
/// "unknown <what> "<name>"; did you mean "<match>"? The <what>s are a, b, c".
std::string unknown_name_message(std::string_view what, std::string_view name,
                                 std::span<const std::string_view> known);

/// A spec's parameter list, read by the shape's reader.
class ShapeArguments {
 public:
  /// Splits `parameters` (the text after "NAME:", nothing when the spec has no ':') into
  /// KEY=VALUE items separated by ','. Values are converted only when asked for.
  /// @throws reduced::Error "shape "<shape>": ..." for an item that is not KEY=VALUE with a
  ///         non-empty key and value, or a key given twice.
  ShapeArguments(std::string_view shape, std::optional<std::string_view> parameters);

  /// Parameter `key` as a number within `bounds`, or `fallback` when not given; recorded for
  /// canonical().
  /// @throws reduced::Error "shape "<shape>": <key>: expected <bounds>, got <text>" for a value
  ///         that is no finite number or out of bounds.
  double number(std::string_view key, double fallback, const Bounds& bounds);
  /// As number(), for an integer (an integral number: "32" or "3.2e1").
  int integer(std::string_view key, int fallback, const Bounds& bounds);
  /// @throws reduced::Error at the first given key no number() or integer() asked for
  ///         (unknown_name_message() over the keys asked for).
  void refuse_unknown() const;
  /// "<shape>:<key>=<value>,..." over the keys asked for, in the order asked, each value the one
  /// used (given or default) as format_number() writes it.
  std::string canonical() const;
  /// Throws reduced::Error "shape "<shape>": <key>: <message>".
  [[noreturn]] void fail(std::string_view key, const std::string& message) const;

 private:
  /// The value of `key` (given or `fallback`) checked against `bounds`; `noun` is "a number" or
  /// "an integer".
  double read(std::string_view key, double fallback, const Bounds& bounds, std::string_view noun,
              bool integral);

  std::string m_shape;
  std::vector<std::pair<std::string, std::string>> m_given;  ///< KEY, VALUE as written.
  std::vector<std::pair<std::string, double>> m_used;        ///< KEY, value, in order asked.
};

}  // namespace khz::scene::detail
