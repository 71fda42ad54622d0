#pragma once
// Reading JSON values with their key paths: conversions whose failures name the file, the path
// of the offending key, what was expected and what was found.

#include <khz/scene/scene_error.hpp>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace khz::scene::detail {

using Json = nlohmann::json;

/// Where a value is in a scene: the scene's source name and the value's key path.
struct Location {
  std::string source;
  std::string path;  ///< "objects[1].model.basis.r"; empty for the whole file.

  Location child(std::string_view key) const;
  Location element(std::size_t index) const;
  /// Throws SceneError at this location.
  [[noreturn]] void fail(const std::string& message) const;
  /// Throws SceneError "expected <what>, got <found>".
  [[noreturn]] void expected(std::string_view what, const Json& found) const;
};

/// An allowed range of numbers and its wording: "a number > 0", "an integer in [1, 1024]".
struct Bounds {
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  bool low_open = false;
  bool high_open = false;
  /// Replaces the generated wording when not empty ("a number ≥ √3 ≈ 1.732").
  std::string text;

  bool contains(double value) const noexcept;
  /// "<noun> ≥ 1" and so on; noun is "a number" or "an integer".
  std::string describe(std::string_view noun) const;
};

Bounds any_value();
Bounds at_least(double low);                    ///< [low, ∞)
Bounds above(double low);                       ///< (low, ∞)
Bounds closed(double low, double high);         ///< [low, high]
Bounds half_open(double low, double high);      ///< [low, high)
Bounds open_closed(double low, double high);    ///< (low, high]
Bounds open_interval(double low, double high);  ///< (low, high)
/// `bounds` worded as `text`.
Bounds with_text(Bounds bounds, std::string text);

/// A number as a message shows it: integers without a fraction, others as the shortest text
/// that reads back to the same double.
std::string format_number(double value);
/// `text` in double quotes.
std::string in_quotes(std::string_view text);
/// How a message shows a found value: JSON text (shortened when long).
std::string describe_value(const Json& value);
/// The candidate `word` most likely is a typo of (case-insensitive edits, transpositions
/// included: one per four letters of `word`, at least one and at most two; none below three
/// letters), if any.
std::optional<std::string_view> closest_match(std::string_view word,
                                              std::span<const std::string_view> candidates);

/// Parses JSON text. A syntax error becomes SceneError at nlohmann's line and column, a
/// number too large for a double or a key repeated within one object a SceneError at its key
/// path.
Json parse_json(std::string_view text, const std::string& source);

/// A JSON name of an enumerator.
template <typename E>
struct Named {
  std::string_view name;
  E value;
};

double to_number(const Json& value, const Location& at, const Bounds& bounds);
/// An integer (an integral float such as 64.0 or 1e3 counts) within `bounds` and within
/// [type_low, type_high], the range of the type it will be stored in.
std::int64_t to_integer(const Json& value, const Location& at, const Bounds& bounds,
                        std::int64_t type_low, std::int64_t type_high);
/// An integer in [0, 2⁶⁴ − 1] (seeds).
std::uint64_t to_seed(const Json& value, const Location& at);
bool to_boolean(const Json& value, const Location& at);
/// A non-empty string.
std::string to_string(const Json& value, const Location& at);
/// An array of three finite numbers.
Eigen::Vector3d to_vector3(const Json& value, const Location& at);
/// Throws "expected one of "a", "b" or "c", got …" (with a suggestion when one is close).
[[noreturn]] void fail_choice(const Json& value, const Location& at,
                              std::span<const std::string_view> names);

/// The enumerator `value` names.
template <typename E, std::size_t N>
E to_choice(const Json& value, const Location& at, const std::array<Named<E>, N>& table) {
  if (value.is_string()) {
    const std::string& text = value.get_ref<const std::string&>();
    for (const Named<E>& entry : table) {
      if (entry.name == text) return entry.value;
    }
  }
  std::array<std::string_view, N> names;
  for (std::size_t i = 0; i < N; ++i) names[i] = table[i].name;
  fail_choice(value, at, names);
}

/// The JSON name of `value` in `table`.
template <typename E, std::size_t N>
std::string_view name_of(E value, const std::array<Named<E>, N>& table) {
  for (const Named<E>& entry : table) {
    if (entry.value == value) return entry.name;
  }
  return "?";
}

/// A JSON object being read: it refuses unknown keys on construction, then hands out its
/// members converted and checked, each failure naming the member's key path.
class ObjectReader {
 public:
  /// A hint for an unknown key that is no typo of a known one: {"resolution", "cells"}.
  using Hint = std::pair<std::string_view, std::string_view>;

  /// @throws SceneError if `value` is not an object, or at its first key not in `known`
  ///         ("did you mean" the closest known key, else the target of the closest hint, else
  ///         the list of known keys). On a tie the earlier known key is suggested.
  ObjectReader(const Json& value, Location location, std::span<const std::string_view> known,
               std::initializer_list<Hint> hints = {});
  ObjectReader(const Json& value, Location location, std::initializer_list<std::string_view> known,
               std::initializer_list<Hint> hints = {})
      : ObjectReader(value, std::move(location), std::span(known.begin(), known.size()), hints) {}

  const Location& location() const noexcept { return m_location; }
  /// The location of member `key`.
  Location at(std::string_view key) const { return m_location.child(key); }
  bool has(std::string_view key) const { return m_value.contains(key); }
  /// Member `key`; precondition: has(key).
  const Json& value(std::string_view key) const { return m_value.at(key); }
  /// Member `key`. @throws SceneError "missing required key "<key>" (<what>)" at this object.
  const Json& required(std::string_view key, std::string_view what) const;
  /// Throws SceneError at member `key`.
  [[noreturn]] void fail(std::string_view key, const std::string& message) const {
    at(key).fail(message);
  }
  /// Fails at the first of `keys` present: "applies only to <context>".
  void refuse(std::span<const std::string_view> keys, const std::string& context) const;
  void refuse(std::initializer_list<std::string_view> keys, const std::string& context) const {
    refuse(std::span(keys.begin(), keys.size()), context);
  }

  double number(std::string_view key, double fallback, const Bounds& bounds) const;
  double required_number(std::string_view key, const Bounds& bounds, std::string_view what) const;
  template <typename Int>
  Int integer(std::string_view key, Int fallback, const Bounds& bounds) const {
    return has(key) ? convert_integer<Int>(value(key), at(key), bounds) : fallback;
  }
  template <typename Int>
  Int required_integer(std::string_view key, const Bounds& bounds, std::string_view what) const {
    return convert_integer<Int>(required(key, what), at(key), bounds);
  }
  std::uint64_t seed(std::string_view key, std::uint64_t fallback) const;
  bool boolean(std::string_view key, bool fallback) const;
  std::string required_string(std::string_view key, std::string_view what) const;
  Eigen::Vector3d vector3(std::string_view key, const Eigen::Vector3d& fallback) const;
  Eigen::Vector3d required_vector3(std::string_view key, std::string_view what) const;
  template <typename E, std::size_t N>
  E choice(std::string_view key, E fallback, const std::array<Named<E>, N>& table) const {
    return has(key) ? to_choice(value(key), at(key), table) : fallback;
  }
  /// Member `key` as an object reader, or nothing when absent.
  std::optional<ObjectReader> object(std::string_view key, std::span<const std::string_view> known,
                                     std::initializer_list<Hint> hints = {}) const;
  std::optional<ObjectReader> object(std::string_view key,
                                     std::initializer_list<std::string_view> known,
                                     std::initializer_list<Hint> hints = {}) const {
    return object(key, std::span(known.begin(), known.size()), hints);
  }
  /// Member `key`, which must be an array when present; nullptr when absent.
  const Json* array(std::string_view key) const;

 private:
  template <typename Int>
  static Int convert_integer(const Json& value, const Location& at, const Bounds& bounds) {
    return static_cast<Int>(to_integer(value, at, bounds, std::numeric_limits<Int>::min(),
                                       std::numeric_limits<Int>::max()));
  }

  const Json& m_value;
  Location m_location;
};

}  // namespace khz::scene::detail
