#include <khz/reduced/basis/force_load.hpp>
#include <khz/reduced/errors.hpp>

#include "detail/file_bytes.hpp"
#include "detail/number_text.hpp"
#include "detail/text_scanner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

namespace khz::reduced {
namespace {

using detail::TextScanner;

constexpr std::array<std::string_view, 5> column_names = {"load", "vertex", "fx", "fy", "fz"};
constexpr std::string_view header_text = "load,vertex,fx,fy,fz";
constexpr std::string_view utf8_bom = "\xEF\xBB\xBF";

std::string_view trim(std::string_view text) noexcept {
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

/// Splits a CSV line at commas into trimmed fields; returns how many there are (fields beyond
/// the array are counted, not stored).
std::size_t split_fields(std::string_view line, std::array<std::string_view, 5>& fields) {
  std::size_t count = 0;
  for (;;) {
    const std::size_t comma = line.find(',');
    const std::string_view field = trim(line.substr(0, comma));
    if (count < fields.size()) fields[count] = field;
    ++count;
    if (comma == std::string_view::npos) return count;
    line.remove_prefix(comma + 1);
  }
}

std::int64_t integer_field(const TextScanner& scanner, std::string_view field,
                           std::string_view what) {
  std::int64_t value = 0;
  if (!detail::parse_integer(field, value)) {
    scanner.fail("expected " + std::string(what) + " (an integer), found " +
                 detail::quoted_token(field));
  }
  return value;
}

double number_field(const TextScanner& scanner, std::string_view field, std::string_view what) {
  double value = 0.0;
  if (!detail::parse_double(field, value)) {
    scanner.fail("expected " + std::string(what) + " (a finite number), found " +
                 detail::quoted_token(field));
  }
  return value;
}

void read_header(TextScanner& scanner) {
  scanner.require_content_line('#', "the header '" + std::string(header_text) + "'");
  const std::string_view line = scanner.rest_of_line();
  std::array<std::string_view, 5> fields;
  const std::size_t count = split_fields(line, fields);
  if (count != fields.size() || !std::equal(fields.begin(), fields.end(), column_names.begin())) {
    scanner.fail("expected the header '" + std::string(header_text) + "', found " +
                 detail::quoted_token(trim(line)));
  }
}

/// The load's forces summed per dof: (dof, value) with increasing dofs.
std::vector<std::pair<std::int64_t, double>> sparse_entries(const ForceLoad& load,
                                                            std::size_t index) {
  std::vector<std::pair<std::int64_t, double>> entries;
  entries.reserve(3 * load.forces.size());
  for (std::size_t p = 0; p < load.forces.size(); ++p) {
    const PointForce& point = load.forces[p];
    if (point.vertex < 0 || !point.force.allFinite()) {
      throw Error("force_distances: load " + std::to_string(index) + ", point force " +
                  std::to_string(p) + ": negative vertex or non-finite force");
    }
    for (int c = 0; c < 3; ++c) {
      entries.emplace_back(3 * std::int64_t{point.vertex} + c, point.force[c]);
    }
  }
  // Stable, so repeated vertices add up in input order, as in to_vector().
  std::stable_sort(entries.begin(), entries.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::size_t kept = 0;
  for (std::size_t e = 0; e < entries.size(); ++e) {
    if (kept > 0 && entries[kept - 1].first == entries[e].first) {
      entries[kept - 1].second += entries[e].second;
    } else {
      entries[kept++] = entries[e];
    }
  }
  entries.resize(kept);
  return entries;
}

/// ‖a − b‖ for two sparse vectors with increasing indices, by a merge.
double difference_norm(const std::vector<std::pair<std::int64_t, double>>& a,
                       const std::vector<std::pair<std::int64_t, double>>& b) {
  double sum = 0.0;
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < a.size() || j < b.size()) {
    double d = 0.0;
    if (j == b.size() || (i < a.size() && a[i].first < b[j].first)) {
      d = a[i++].second;
    } else if (i == a.size() || b[j].first < a[i].first) {
      d = -b[j++].second;
    } else {
      d = a[i++].second - b[j++].second;
    }
    sum += d * d;
  }
  return std::sqrt(sum);
}

}  // namespace

void ForceLoad::validate(Eigen::Index num_vertices) const {
  for (std::size_t p = 0; p < forces.size(); ++p) {
    const PointForce& point = forces[p];
    if (point.vertex < 0 || point.vertex >= num_vertices) {
      throw Error("point force " + std::to_string(p) + " acts on vertex " +
                  std::to_string(point.vertex) + ", but the mesh has " +
                  std::to_string(num_vertices) + " vertices");
    }
    if (!point.force.allFinite()) {
      throw Error("point force " + std::to_string(p) + " (vertex " + std::to_string(point.vertex) +
                  ") is not finite");
    }
  }
}

Eigen::VectorXd ForceLoad::to_vector(Eigen::Index num_vertices) const {
  validate(num_vertices);
  Eigen::VectorXd full = Eigen::VectorXd::Zero(3 * num_vertices);
  for (const PointForce& point : forces) full.segment<3>(3 * point.vertex) += point.force;
  return full;
}

Eigen::MatrixXd force_distances(std::span<const ForceLoad> loads) {
  const auto n = static_cast<Eigen::Index>(loads.size());
  std::vector<std::vector<std::pair<std::int64_t, double>>> entries;
  entries.reserve(loads.size());
  for (std::size_t l = 0; l < loads.size(); ++l) entries.push_back(sparse_entries(loads[l], l));
  Eigen::MatrixXd distances = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < j; ++i) {
      const double d = difference_norm(entries[static_cast<std::size_t>(i)],
                                       entries[static_cast<std::size_t>(j)]);
      distances(i, j) = d;
      distances(j, i) = d;
    }
  }
  return distances;
}

std::vector<ForceLoad> parse_force_loads(std::string_view data, const std::string& source,
                                         Eigen::Index num_vertices) {
  if (data.starts_with(utf8_bom)) data.remove_prefix(utf8_bom.size());
  TextScanner scanner(data, source);
  read_header(scanner);
  std::vector<ForceLoad> loads;
  std::array<std::string_view, 5> fields;
  while (scanner.next_content_line('#')) {
    const std::size_t count = split_fields(scanner.rest_of_line(), fields);
    if (count != fields.size()) {
      scanner.fail("expected 5 comma-separated fields '" + std::string(header_text) + "', found " +
                   std::to_string(count));
    }
    const std::int64_t id = integer_field(scanner, fields[0], "a load id");
    const auto current = static_cast<std::int64_t>(loads.size()) - 1;
    // The current load's id (once there is one) or the next.
    if (!(id == current + 1 || (id == current && !loads.empty()))) {
      scanner.fail("load id " + std::to_string(id) + " is out of sequence: expected " +
                   (current < 0 ? std::string("0")
                                : std::to_string(current) + " or " + std::to_string(current + 1)) +
                   " (ids count up from 0 and the rows of a load are consecutive)");
    }
    if (id == current + 1) loads.emplace_back();
    const std::int64_t vertex = integer_field(scanner, fields[1], "a vertex index");
    if (vertex < 0 || vertex >= num_vertices) {
      scanner.fail("vertex " + std::to_string(vertex) + " is out of range: the mesh has " +
                   std::to_string(num_vertices) + " vertices");
    }
    PointForce point;
    point.vertex = static_cast<int>(vertex);
    for (int c = 0; c < 3; ++c) {
      point.force[c] = number_field(scanner, fields[static_cast<std::size_t>(2 + c)],
                                    "force component " + std::string(column_names[2 + c]));
    }
    loads.back().forces.push_back(point);
  }
  return loads;
}

std::string format_force_loads(std::span<const ForceLoad> loads) {
  std::string out(header_text);
  out += '\n';
  for (std::size_t l = 0; l < loads.size(); ++l) {
    if (loads[l].forces.empty()) {
      throw Error("format_force_loads: load " + std::to_string(l) +
                  " has no point forces; the load file cannot represent an empty load");
    }
    for (const PointForce& point : loads[l].forces) {
      if (!point.force.allFinite()) {
        throw Error("format_force_loads: load " + std::to_string(l) + " has a non-finite force");
      }
      detail::append_number(out, l);
      out += ',';
      detail::append_number(out, point.vertex);
      for (int c = 0; c < 3; ++c) {
        out += ',';
        detail::append_number(out, point.force[c]);
      }
      out += '\n';
    }
  }
  return out;
}

std::vector<ForceLoad> read_force_loads(const std::filesystem::path& file,
                                        Eigen::Index num_vertices) {
  return parse_force_loads(detail::read_file_bytes(file), file.string(), num_vertices);
}

void write_force_loads(const std::filesystem::path& file, std::span<const ForceLoad> loads) {
  detail::write_file_bytes(file, format_force_loads(loads));
}

}  // namespace khz::reduced
