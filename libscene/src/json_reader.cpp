#include "json_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <set>

namespace khz::scene::detail {
namespace {

/// Found values longer than this are shortened in messages.
constexpr std::size_t longest_shown = 60;

std::string shorten(std::string text) {
  if (text.size() <= longest_shown) return text;
  text.resize(longest_shown);
  return text + "...";
}

char lower(char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); }

/// Optimal string alignment distance (edits, with adjacent transpositions), ignoring case.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1])) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[a.size()][b.size()];
}

/// "\"a\", \"b\" or \"c\"".
std::string alternatives(std::span<const std::string_view> names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) text += i + 1 == names.size() ? " or " : ", ";
    text += in_quotes(names[i]);
  }
  return text;
}

/// The line and column nlohmann/json put in a parse error's message ("parse error at line 4,
/// column 2: <detail>"), and the detail; counted from the byte offset if the text differs.
void syntax_error_position(const Json::parse_error& error, std::string_view text, int& line,
                           int& column, std::string& detail) {
  const std::string what = error.what();
  const std::size_t at = what.find("at line ");
  if (at != std::string::npos &&
      std::sscanf(what.c_str() + at, "at line %d, column %d", &line, &column) == 2) {
    const std::size_t colon = what.find(": ", at);
    detail = colon == std::string::npos ? what : what.substr(colon + 2);
    return;
  }
  const std::size_t end = std::min<std::size_t>(error.byte, text.size());
  line = 1;
  column = 0;
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 0;
    } else {
      ++column;
    }
  }
  const std::size_t colon = what.find(": ");
  detail = colon == std::string::npos ? what : what.substr(colon + 2);
}

}  // namespace

Location Location::child(std::string_view key) const {
  return {source, path.empty() ? std::string(key) : path + "." + std::string(key)};
}

Location Location::element(std::size_t index) const {
  return {source, path + "[" + std::to_string(index) + "]"};
}

void Location::fail(const std::string& message) const {
  throw SceneError::at_key(source, path, message);
}

void Location::expected(std::string_view what, const Json& found) const {
  fail("expected " + std::string(what) + ", got " + describe_value(found));
}

bool Bounds::contains(double value) const noexcept {
  if (!std::isfinite(value)) return false;
  const bool above_low = low_open ? value > low : value >= low;
  const bool below_high = high_open ? value < high : value <= high;
  return above_low && below_high;
}

std::string Bounds::describe(std::string_view noun) const {
  if (!text.empty()) return text;
  const bool has_low = std::isfinite(low);
  const bool has_high = std::isfinite(high);
  std::string result(noun);
  if (has_low && has_high) {
    result += std::string(" in ") + (low_open ? "(" : "[") + format_number(low) + ", " +
              format_number(high) + (high_open ? ")" : "]");
  } else if (has_low) {
    result += (low_open ? " > " : " ≥ ") + format_number(low);
  } else if (has_high) {
    result += (high_open ? " < " : " ≤ ") + format_number(high);
  }
  return result;
}

Bounds any_value() { return {}; }

Bounds at_least(double low) {
  Bounds bounds;
  bounds.low = low;
  return bounds;
}

Bounds above(double low) {
  Bounds bounds = at_least(low);
  bounds.low_open = true;
  return bounds;
}

Bounds closed(double low, double high) {
  Bounds bounds = at_least(low);
  bounds.high = high;
  return bounds;
}

Bounds half_open(double low, double high) {
  Bounds bounds = closed(low, high);
  bounds.high_open = true;
  return bounds;
}

Bounds open_closed(double low, double high) {
  Bounds bounds = closed(low, high);
  bounds.low_open = true;
  return bounds;
}

Bounds open_interval(double low, double high) {
  Bounds bounds = half_open(low, high);
  bounds.low_open = true;
  return bounds;
}

Bounds with_text(Bounds bounds, std::string text) {
  bounds.text = std::move(text);
  return bounds;
}

std::string format_number(double value) {
  if (std::isfinite(value) && value == std::floor(value) && std::abs(value) < 1e15) {
    return std::to_string(static_cast<long long>(value));
  }
  char buffer[64];
  const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string in_quotes(std::string_view text) {
  // Appends, not "\"" + std::string(…): GCC 12 reports a false -Wrestrict for the latter.
  std::string result;
  result.reserve(text.size() + 2);
  result += '"';
  result += text;
  result += '"';
  return result;
}

std::string describe_value(const Json& value) { return shorten(value.dump()); }

std::optional<std::string_view> closest_match(std::string_view word,
                                              std::span<const std::string_view> candidates) {
  // One edit per four letters, at least one and at most two: "resoluton" → "resolution", but
  // not "nodes" → "none"; words under three letters only differ in case ("x" is no "r").
  const std::size_t allowed = word.size() < 3 ? 0 : std::clamp<std::size_t>(word.size() / 4, 1, 2);
  std::optional<std::string_view> best;
  std::size_t best_distance = allowed + 1;
  for (const std::string_view candidate : candidates) {
    const std::size_t distance = edit_distance(word, candidate);
    if (distance < best_distance) {
      best = candidate;
      best_distance = distance;
    }
  }
  return best;
}

Json parse_json(std::string_view text, const std::string& source) {
  // The key path of the value being parsed, to name repeated keys and numbers that overflow.
  struct Frame {
    bool object = false;
    std::string path;
    std::set<std::string> keys;
    std::string key;       // objects: the key of the current member
    std::size_t next = 0;  // arrays: index of the next element
  };
  std::vector<Frame> frames;
  const auto next_path = [&frames]() -> std::string {
    if (frames.empty()) return {};
    Frame& top = frames.back();
    if (top.object) return Location{{}, top.path}.child(top.key).path;
    return Location{{}, top.path}.element(top.next++).path;
  };
  const Json::parser_callback_t callback = [&](int, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
        frames.push_back({true, next_path(), {}, {}, 0});
        break;
      case Json::parse_event_t::array_start:
        frames.push_back({false, next_path(), {}, {}, 0});
        break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        frames.pop_back();
        break;
      case Json::parse_event_t::key: {
        Frame& top = frames.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second) {
          Location{source, top.path}.child(top.key).fail(
              "duplicate key: an object may name each key once");
        }
        break;
      }
      case Json::parse_event_t::value:
        if (!frames.empty() && !frames.back().object) ++frames.back().next;
        break;
    }
    return true;
  };
  try {
    return Json::parse(text, callback);
  } catch (const Json::parse_error& error) {
    int line = 0;
    int column = 0;
    std::string detail;
    syntax_error_position(error, text, line, column, detail);
    throw SceneError::at_position(source, line, column, "JSON syntax error: " + detail);
  } catch (const Json::out_of_range& error) {
    // A number beyond the range of a double (nlohmann/json error 406), at the current key.
    std::string path;
    if (!frames.empty()) {
      const Frame& top = frames.back();
      path = top.object ? Location{{}, top.path}.child(top.key).path
                        : Location{{}, top.path}.element(top.next).path;
    }
    const std::string what = error.what();
    const std::size_t bracket = what.find("] ");
    throw SceneError::at_key(
        source, path,
        "number out of range: " + (bracket == std::string::npos ? what : what.substr(bracket + 2)));
  }
}

double to_number(const Json& value, const Location& at, const Bounds& bounds) {
  if (!value.is_number() || !bounds.contains(value.get<double>())) {
    at.expected(bounds.describe("a number"), value);
  }
  return value.get<double>();
}

std::int64_t to_integer(const Json& value, const Location& at, const Bounds& bounds,
                        std::int64_t type_low, std::int64_t type_high) {
  const std::string expected = bounds.describe("an integer");
  std::int64_t result = 0;
  if (value.is_number_unsigned()) {
    const std::uint64_t unsigned_value = value.get<std::uint64_t>();
    if (unsigned_value > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      at.fail("expected " + expected + ", got " + describe_value(value) + " (too large)");
    }
    result = static_cast<std::int64_t>(unsigned_value);
  } else if (value.is_number_integer()) {
    result = value.get<std::int64_t>();
  } else if (value.is_number_float()) {
    const double number = value.get<double>();
    if (!(number == std::floor(number)) || !(std::abs(number) < 9e18)) {
      at.expected(expected, value);
    }
    result = static_cast<std::int64_t>(number);
  } else {
    at.expected(expected, value);
  }
  if (!bounds.contains(static_cast<double>(result))) at.expected(expected, value);
  if (result < type_low || result > type_high) {
    at.fail("expected " + expected + ", got " + describe_value(value) + " (outside [" +
            std::to_string(type_low) + ", " + std::to_string(type_high) + "])");
  }
  return result;
}

std::uint64_t to_seed(const Json& value, const Location& at) {
  if (value.is_number_unsigned()) return value.get<std::uint64_t>();
  if (value.is_number_integer() && value.get<std::int64_t>() >= 0) {
    return static_cast<std::uint64_t>(value.get<std::int64_t>());
  }
  at.expected("an integer in [0, 2^64 - 1]", value);
}

bool to_boolean(const Json& value, const Location& at) {
  if (!value.is_boolean()) at.expected("true or false", value);
  return value.get<bool>();
}

std::string to_string(const Json& value, const Location& at) {
  if (!value.is_string() || value.get_ref<const std::string&>().empty()) {
    at.expected("a non-empty string", value);
  }
  return value.get<std::string>();
}

Eigen::Vector3d to_vector3(const Json& value, const Location& at) {
  const bool ok = value.is_array() && value.size() == 3 &&
                  std::all_of(value.begin(), value.end(), [](const Json& entry) {
                    return entry.is_number() && std::isfinite(entry.get<double>());
                  });
  if (!ok) at.expected("an array of 3 numbers [x, y, z]", value);
  return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

void fail_choice(const Json& value, const Location& at, std::span<const std::string_view> names) {
  std::string message =
      "expected " + (names.size() == 1 ? in_quotes(names[0]) : "one of " + alternatives(names)) +
      ", got " + describe_value(value);
  if (value.is_string()) {
    if (const auto match = closest_match(value.get_ref<const std::string&>(), names)) {
      message += "; did you mean " + in_quotes(*match) + "?";
    }
  }
  at.fail(message);
}

ObjectReader::ObjectReader(const Json& value, Location location,
                           std::span<const std::string_view> known,
                           std::initializer_list<Hint> hints)
    : m_value(value), m_location(std::move(location)) {
  if (!value.is_object()) m_location.expected("an object {...}", value);
  const std::vector<std::string_view> keys(known.begin(), known.end());
  for (const auto& member : value.items()) {
    const std::string& key = member.key();
    if (std::find(keys.begin(), keys.end(), key) != keys.end()) continue;
    // A typo of a known key, else the key a hint names for the word (or a typo of it).
    std::optional<std::string_view> suggestion = closest_match(key, keys);
    if (!suggestion) {
      std::vector<std::string_view> hinted;
      for (const Hint& hint : hints) hinted.push_back(hint.first);
      if (const auto match = closest_match(key, hinted)) {
        for (const Hint& hint : hints) {
          if (hint.first == *match) suggestion = hint.second;
        }
      }
    }
    std::string message = "unknown key";
    if (suggestion) {
      message += "; did you mean " + in_quotes(*suggestion) + "?";
    } else {
      std::vector<std::string_view> sorted = keys;
      std::sort(sorted.begin(), sorted.end());
      message += "; the keys here are ";
      for (std::size_t i = 0; i < sorted.size(); ++i) {
        message += (i > 0 ? ", " : "") + std::string(sorted[i]);
      }
    }
    at(key).fail(message);
  }
}

const Json& ObjectReader::required(std::string_view key, std::string_view what) const {
  if (!has(key)) {
    m_location.fail("missing required key " + in_quotes(key) + " (" + std::string(what) + ")");
  }
  return value(key);
}

void ObjectReader::refuse(std::span<const std::string_view> keys,
                          const std::string& context) const {
  for (const std::string_view key : keys) {
    if (has(key)) fail(key, "applies only to " + context);
  }
}

double ObjectReader::number(std::string_view key, double fallback, const Bounds& bounds) const {
  return has(key) ? to_number(value(key), at(key), bounds) : fallback;
}

double ObjectReader::required_number(std::string_view key, const Bounds& bounds,
                                     std::string_view what) const {
  return to_number(required(key, what), at(key), bounds);
}

std::uint64_t ObjectReader::seed(std::string_view key, std::uint64_t fallback) const {
  return has(key) ? to_seed(value(key), at(key)) : fallback;
}

bool ObjectReader::boolean(std::string_view key, bool fallback) const {
  return has(key) ? to_boolean(value(key), at(key)) : fallback;
}

std::string ObjectReader::required_string(std::string_view key, std::string_view what) const {
  return to_string(required(key, what), at(key));
}

Eigen::Vector3d ObjectReader::vector3(std::string_view key, const Eigen::Vector3d& fallback) const {
  return has(key) ? to_vector3(value(key), at(key)) : fallback;
}

Eigen::Vector3d ObjectReader::required_vector3(std::string_view key, std::string_view what) const {
  return to_vector3(required(key, what), at(key));
}

std::optional<ObjectReader> ObjectReader::object(std::string_view key,
                                                 std::span<const std::string_view> known,
                                                 std::initializer_list<Hint> hints) const {
  if (!has(key)) return std::nullopt;
  return ObjectReader(value(key), at(key), known, hints);
}

const Json* ObjectReader::array(std::string_view key) const {
  if (!has(key)) return nullptr;
  const Json& member = value(key);
  if (!member.is_array()) at(key).expected("an array [...]", member);
  return &member;
}

}  // namespace khz::scene::detail
