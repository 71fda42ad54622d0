#include <khz/series/pvd_collection.hpp>

#include <khz/reduced/errors.hpp>

#include "detail/number_text.hpp"
#include "file_replacement.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <system_error>

namespace khz::series {
namespace {

using reduced::detail::number_text;

/// Names become file names and XML attribute values: letters, digits, '_', '-' and '.', not
/// starting with '.', need neither escaping nor quoting in either.
void check_name(std::string_view name, const std::string& what) {
  const bool allowed = std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
  if (name.empty() || !allowed || name.front() == '.') {
    throw reduced::Error(what + " '" + std::string(name) +
                         "' is not a name of letters, digits, '_', '-' and '.' not starting "
                         "with '.'");
  }
}

/// The part's index-th dataset file, relative to the collection's directory.
std::filesystem::path dataset_file(const std::string& collection, std::string_view part,
                                   std::int64_t index) {
  std::string number = std::to_string(index);
  if (number.size() < 6) number.insert(0, 6 - number.size(), '0');
  return std::filesystem::path(collection) / (std::string(part) + "_" + number + ".vtp");
}

}  // namespace

PvdCollection::PvdCollection(std::filesystem::path directory, std::string name)
    : m_directory(std::move(directory)), m_name(std::move(name)) {
  check_name(m_name, "collection name");
  m_file = m_directory / (m_name + ".pvd");
  const std::filesystem::path datasets = m_directory / m_name;
  std::error_code error;
  std::filesystem::create_directories(datasets, error);
  if (error || !std::filesystem::is_directory(datasets)) {
    throw reduced::IoError(datasets.string() + ": cannot create the folder" +
                           (error ? ": " + error.message() : std::string()));
  }
  write_collection();
}

const PvdEntry& PvdCollection::add(double time, std::string_view part, const DatasetWriter& write) {
  const std::string where = m_file.string() + ": ";
  check_name(part, where + "part name");
  const std::string dataset =
      "dataset of part '" + std::string(part) + "' at time " + number_text(time) + " s";
  if (!std::isfinite(time)) throw reduced::Error(where + dataset + ": the time is not finite");
  if (!m_entries.empty() && time < m_entries.back().time) {
    throw reduced::Error(where + dataset + " is earlier than the previous dataset (" +
                         number_text(m_entries.back().time) + " s)");
  }
  const auto history = m_parts.find(part);
  const PartHistory previous = history != m_parts.end() ? history->second : PartHistory{};
  if (previous.count > 0 && !(time > previous.last_time)) {
    throw reduced::Error(where + dataset + " is not later than the part's previous dataset (" +
                         number_text(previous.last_time) + " s)");
  }

  PvdEntry entry{time, std::string(part), dataset_file(m_name, part, previous.count)};
  write(m_directory / entry.file);
  const std::size_t written_lines = m_dataset_lines.size();
  m_dataset_lines += "    <DataSet timestep=\"" + number_text(time) + "\" part=\"" + entry.part +
                     "\" name=\"" + entry.part + "\" file=\"" + entry.file.generic_string() +
                     "\"/>\n";
  m_entries.push_back(std::move(entry));
  try {
    write_collection();
  } catch (...) {
    m_entries.pop_back();
    m_dataset_lines.resize(written_lines);
    throw;
  }
  m_parts.insert_or_assign(std::string(part), PartHistory{previous.count + 1, time});
  return m_entries.back();
}

void PvdCollection::write_collection() const {
  detail::replace_file(m_file, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n"
           "  <Collection>\n"
        << m_dataset_lines << "  </Collection>\n</VTKFile>\n";
  });
}

}  // namespace khz::series
