#include "shape_arguments.hpp"

#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <system_error>

namespace khz::scene::detail {
namespace {

/// `text` as a finite number, if the whole of it is one.
std::optional<double> parse_number(std::string_view text) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const std::from_chars_result result = std::from_chars(text.data(), end, value);
  if (result.ec != std::errc() || result.ptr != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

}  // namespace

std::string unknown_name_message(std::string_view what, std::string_view name,
                                 std::span<const std::string_view> known) {
  std::string message = "unknown " + std::string(what) + " " + in_quotes(name);
  const std::optional<std::string_view> match = closest_match(name, known);
  message += match ? "; did you mean " + in_quotes(*match) + "? The " : "; the ";
  message += std::string(what) + "s are ";
  std::vector<std::string_view> sorted(known.begin(), known.end());
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    message += (i > 0 ? ", " : "") + std::string(sorted[i]);
  }
  return message;
}

ShapeArguments::ShapeArguments(std::string_view shape, std::optional<std::string_view> parameters)
    : m_shape(shape) {
  if (!parameters) return;
  std::string_view rest = *parameters;
  while (true) {
    const std::size_t comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    const std::size_t equals = item.find('=');
    if (equals == 0 || equals == std::string_view::npos || equals + 1 == item.size()) {
      throw reduced::Error("shape " + in_quotes(m_shape) +
                           ": expected parameters KEY=VALUE separated by ',', got " +
                           in_quotes(item));
    }
    const std::string key(item.substr(0, equals));
    const auto same_key = [&key](const auto& entry) { return entry.first == key; };
    if (std::any_of(m_given.begin(), m_given.end(), same_key)) fail(key, "given twice");
    m_given.emplace_back(key, item.substr(equals + 1));
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
}

double ShapeArguments::read(std::string_view key, double fallback, const Bounds& bounds,
                            std::string_view noun, bool integral) {
  const auto given = std::find_if(m_given.begin(), m_given.end(),
                                  [key](const auto& entry) { return entry.first == key; });
  double value = fallback;
  if (given != m_given.end()) {
    const std::optional<double> parsed = parse_number(given->second);
    if (!parsed || !bounds.contains(*parsed) || (integral && *parsed != std::floor(*parsed))) {
      fail(key, "expected " + bounds.describe(noun) + ", got " +
                    (parsed ? format_number(*parsed) : in_quotes(given->second)));
    }
    value = *parsed;
  }
  m_used.emplace_back(std::string(key), value);
  return value;
}

double ShapeArguments::number(std::string_view key, double fallback, const Bounds& bounds) {
  return read(key, fallback, bounds, "a number", /*integral=*/false);
}

int ShapeArguments::integer(std::string_view key, int fallback, const Bounds& bounds) {
  return static_cast<int>(read(key, fallback, bounds, "an integer", /*integral=*/true));
}

void ShapeArguments::refuse_unknown() const {
  std::vector<std::string_view> known;
  for (const auto& [key, value] : m_used) known.push_back(key);
  for (const auto& [key, text] : m_given) {
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      throw reduced::Error("shape " + in_quotes(m_shape) + ": " +
                           unknown_name_message("parameter", key, known));
    }
  }
}

std::string ShapeArguments::canonical() const {
  std::string text = m_shape;
  for (std::size_t i = 0; i < m_used.size(); ++i) {
    text += (i == 0 ? ":" : ",") + m_used[i].first + "=" + format_number(m_used[i].second);
  }
  return text;
}

void ShapeArguments::fail(std::string_view key, const std::string& message) const {
  throw reduced::Error("shape " + in_quotes(m_shape) + ": " + std::string(key) + ": " + message);
}

}  // namespace khz::scene::detail
