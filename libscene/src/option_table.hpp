#pragma once
// Option tables: the settings a scene file gives an option struct, each declared once — its JSON
// key, the member it sets and the values it accepts — so that reading the block, the block's
// list of keys (unknown keys, "did you mean") and the struct's part of a content key all follow
// from the same list. The defaults are the struct's own: a key left out keeps its member.

#include "json_reader.hpp"
#include "read_common.hpp"

#include <khz/haptic/common.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace khz::scene::detail {

/// One setting of `Options`: its JSON key, how the reader sets the member from the key's value,
/// and the member as canonical JSON (for content keys).
template <typename Options>
struct OptionEntry {
  std::string_view key;
  /// The key's name in content keys: `key`, except where key format 1 spelt the library's name.
  std::string_view canonical_key;
  /// Sets the member from the block's `key` when present, checking the value (type, bounds)
  /// and failing at the key's path; a key left out keeps the member as it is.
  std::function<void(const ObjectReader& block, Options& options)> read;
  /// The member's value as content keys write it.
  std::function<Json(const Options& options)> canonical;

  /// This entry with `name` as its name in content keys.
  OptionEntry named_in_keys(std::string_view name) && {
    canonical_key = name;
    return std::move(*this);
  }
};

/// Bounds that depend on settings read before (the table reads in order).
template <typename Options>
using BoundsOf = std::function<Bounds(const Options& options)>;

/// A number (double member) within `bounds`.
template <typename Options>
OptionEntry<Options> number(std::string_view key, double Options::*member, Bounds bounds) {
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            options.*member = block.number(key, options.*member, bounds);
          },
          [=](const Options& options) { return Json(options.*member); }};
}

/// A number the block must give: missing, it fails with "missing required key "<key>" (<what>)".
template <typename Options>
OptionEntry<Options> required_number(std::string_view key, double Options::*member, Bounds bounds,
                                     std::string_view what) {
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            options.*member = block.required_number(key, bounds, what);
          },
          [=](const Options& options) { return Json(options.*member); }};
}

/// An integer within `bounds` and within the range of the member's type.
template <typename Options, std::integral Int>
OptionEntry<Options> integer(std::string_view key, Int Options::*member, Bounds bounds) {
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            options.*member = block.integer<Int>(key, options.*member, bounds);
          },
          [=](const Options& options) { return Json(options.*member); }};
}

/// An integer the block must give: missing, it fails with "missing required key "<key>" (<what>)".
template <typename Options, std::integral Int>
OptionEntry<Options> required_integer(std::string_view key, Int Options::*member, Bounds bounds,
                                      std::string_view what) {
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            options.*member = block.required_integer<Int>(key, bounds, what);
          },
          [=](const Options& options) { return Json(options.*member); }};
}

/// An integer within bounds that depend on the settings read before it.
template <typename Options, std::integral Int>
OptionEntry<Options> integer(std::string_view key, Int Options::*member,
                             std::type_identity_t<BoundsOf<Options>> bounds) {
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            options.*member = block.integer<Int>(key, options.*member, bounds(options));
          },
          [=](const Options& options) { return Json(options.*member); }};
}

/// An integer that must be one of `allowed`, worded as `text` ("3 or 6").
template <typename Options, std::size_t N>
OptionEntry<Options> integer_of(std::string_view key, int Options::*member,
                                std::array<int, N> allowed, std::string_view text) {
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            if (!block.has(key)) return;
            const auto [low, high] = std::minmax_element(allowed.begin(), allowed.end());
            const int value =
                block.integer<int>(key, 0, with_text(closed(*low, *high), std::string(text)));
            if (std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
              block.at(key).expected(text, block.value(key));
            }
            options.*member = value;
          },
          [=](const Options& options) { return Json(options.*member); }};
}

/// A seed: an integer in [0, 2⁶⁴ − 1].
template <typename Options>
OptionEntry<Options> seed(std::string_view key, std::uint64_t Options::*member) {
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            options.*member = block.seed(key, options.*member);
          },
          [=](const Options& options) { return Json(options.*member); }};
}

/// true or false.
template <typename Options>
OptionEntry<Options> flag(std::string_view key, bool Options::*member) {
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            options.*member = block.boolean(key, options.*member);
          },
          [=](const Options& options) { return Json(options.*member); }};
}

/// One of the names in `names` (static storage: the entry keeps a reference).
template <typename Options, typename E, std::size_t N>
OptionEntry<Options> choice(std::string_view key, E Options::*member,
                            const std::array<Named<E>, N>& names) {
  const std::array<Named<E>, N>* table = &names;
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            options.*member = block.choice(key, options.*member, *table);
          },
          [=](const Options& options) { return Json(name_of(options.*member, *table)); }};
}

/// [x, y, z].
template <typename Options>
OptionEntry<Options> vector3(std::string_view key, Eigen::Vector3d Options::*member) {
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            options.*member = block.vector3(key, options.*member);
          },
          [=](const Options& options) {
            const Eigen::Vector3d& v = options.*member;
            return Json::array({v.x(), v.y(), v.z()});
          }};
}

/// A pose {"position": [x, y, z], "rotation": {"axis", "degrees"}} (read_pose()); its canonical
/// form is the position and the unit quaternion [w, x, y, z] it was read as.
template <typename Options>
OptionEntry<Options> pose(std::string_view key, haptic::Pose Options::*member) {
  return {key, key,
          [=](const ObjectReader& block, Options& options) {
            if (block.has(key)) options.*member = read_pose(block.value(key), block.at(key));
          },
          [=](const Options& options) {
            const haptic::Pose& p = options.*member;
            return Json{
                {"position", {p.position.x(), p.position.y(), p.position.z()}},
                {"orientation",
                 {p.orientation.w(), p.orientation.x(), p.orientation.y(), p.orientation.z()}}};
          }};
}

/// `entry` of a struct that `Outer` holds as `part` (NewmarkParameters within
/// ReducedNewmarkOptions): the same key, one level down.
template <typename Outer, typename Inner>
OptionEntry<Outer> within(Inner Outer::*part, OptionEntry<Inner> entry) {
  return {entry.key, entry.canonical_key,
          [part, read = std::move(entry.read)](const ObjectReader& block, Outer& options) {
            read(block, options.*part);
          },
          [part, canonical = std::move(entry.canonical)](const Outer& options) {
            return canonical(options.*part);
          }};
}

template <typename Options>
class OptionTable;

/// Every entry of `table`, for a struct that `Outer` holds as `part`.
template <typename Outer, typename Inner>
std::vector<OptionEntry<Outer>> within(Inner Outer::*part, const OptionTable<Inner>& table) {
  std::vector<OptionEntry<Outer>> entries;
  for (const OptionEntry<Inner>& entry : table.entries()) entries.push_back(within(part, entry));
  return entries;
}

/// A nested block {...} under `key` whose keys are `table`'s, setting the member `part`.
template <typename Options, typename Inner>
OptionEntry<Options> block(std::string_view key, Inner Options::*part,
                           const OptionTable<Inner>& table) {
  const OptionTable<Inner>* inner = &table;
  return {key, key,
          [=](const ObjectReader& outer, Options& options) {
            if (const auto nested = outer.object(key, inner->keys())) {
              inner->read(*nested, options.*part);
            }
          },
          [=](const Options& options) { return inner->canonical(options.*part); }};
}

/// The settings of one option struct, in the order the reader reads them (a bound may depend on
/// an earlier setting) — and the order of the block's keys for "did you mean".
template <typename Options>
class OptionTable {
 public:
  OptionTable(std::initializer_list<OptionEntry<Options>> entries)
      : OptionTable(std::vector<OptionEntry<Options>>(entries)) {}
  explicit OptionTable(std::vector<OptionEntry<Options>> entries) : m_entries(std::move(entries)) {
    for (const OptionEntry<Options>& entry : m_entries) m_keys.push_back(entry.key);
  }

  std::span<const OptionEntry<Options>> entries() const noexcept { return m_entries; }
  /// The JSON keys, in table order.
  std::span<const std::string_view> keys() const noexcept { return m_keys; }

  /// Sets the member of every key `block` has, in table order; the others keep their values.
  /// @throws SceneError at the first value refused.
  void read(const ObjectReader& block, Options& options) const {
    for (const OptionEntry<Options>& entry : m_entries) entry.read(block, options);
  }

  /// Sets only the member of `key`: a setting that decides which others apply. Precondition:
  /// `key` is one of keys().
  void read(const ObjectReader& block, Options& options, std::string_view key) const {
    for (const OptionEntry<Options>& entry : m_entries) {
      if (entry.key == key) entry.read(block, options);
    }
  }

  /// Every setting as canonical JSON, {name in content keys: value}.
  Json canonical(const Options& options) const {
    Json result = Json::object();
    for (const OptionEntry<Options>& entry : m_entries) {
      result[std::string(entry.canonical_key)] = entry.canonical(options);
    }
    return result;
  }

 private:
  std::vector<OptionEntry<Options>> m_entries;
  std::vector<std::string_view> m_keys;
};

/// A block's keys in order: single keys (std::string_view) and every key of tables, each once.
class KeyList {
 public:
  template <typename... Parts>
  explicit KeyList(const Parts&... parts) {
    (add(parts), ...);
  }
  operator std::span<const std::string_view>() const noexcept { return m_keys; }

 private:
  void add(std::string_view key) {
    if (std::find(m_keys.begin(), m_keys.end(), key) == m_keys.end()) m_keys.push_back(key);
  }
  template <typename Options>
  void add(const OptionTable<Options>& table) {
    for (const std::string_view key : table.keys()) add(key);
  }

  std::vector<std::string_view> m_keys;
};

/// The option table of `Options`: declared for each struct a scene sets in option_tables.hpp,
/// defined in <library>_option_tables.cpp.
template <typename Options>
const OptionTable<Options>& option_table();

}  // namespace khz::scene::detail
