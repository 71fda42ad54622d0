#pragma once
// The ParaView collection (.pvd) that makes a run's frames one time series.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace khz::series {

/// One dataset of a collection.
struct PvdEntry {
  double time = 0.0;  ///< Simulation time, seconds.
  std::string part;   ///< The part it shows, e.g. "dino", "points", "forces".
  /// The dataset file relative to the collection's directory: "<name>/<part>_<index>.vtp".
  std::filesystem::path file;
};

/// A ParaView collection `<directory>/<name>.pvd` listing the datasets of a run, written again
/// after every dataset (through a temporary file renamed over it), so a run that is still
/// going, or was stopped, can be opened at any moment and shows every frame written so far.
///
/// Each dataset is a DataSet element with the attributes timestep (the time, written so that
/// it reads back as the same double), part and name (both the part name; ParaView names the
/// blocks of a time step after it) and file. ParaView shows the datasets of one time step as
/// one multiblock dataset, blocks in the order added: add the same parts in the same order at
/// every time step (the first time step decides whether the reader makes a multiblock at all).
///
/// Rewriting costs O(datasets so far) per add(): about 100 bytes per dataset. Not thread-safe:
/// one thread adds.
class PvdCollection {
 public:
  /// Writes a dataset to the file it is given, or throws.
  using DatasetWriter = std::function<void(const std::filesystem::path& file)>;

  /// Creates `directory` and `directory/name` (the datasets' folder) if missing and writes an
  /// empty collection `directory/name.pvd`, replacing one from an earlier run (its dataset
  /// files are left; this collection overwrites them as it reaches their names).
  /// @param name Base name: letters, digits, '_', '-' and '.', not starting with '.'.
  /// @throws reduced::Error if `name` is not such a name; reduced::IoError naming the folder
  ///         or file that cannot be created or written.
  PvdCollection(std::filesystem::path directory, std::string name);

  /// Adds one dataset: checks `time` and `part`, has `write` write the dataset to
  /// `directory/name/<part>_<index>.vtp` (index: the part's datasets before this one, at
  /// least six digits), records it and rewrites the .pvd. On any failure the collection is
  /// left as it was (a dataset file already written stays on disk and is overwritten by the
  /// part's next dataset).
  /// @param time Seconds: finite, not earlier than the previous dataset's time and later than
  ///        the previous time of the same part (several parts share a time step).
  /// @param part Letters, digits, '_', '-' and '.', not starting with '.'.
  /// @param write Called once, after the checks.
  /// @return The new entry (valid until the next add()).
  /// @throws reduced::Error naming the collection, before `write` is called, if `time` or
  ///         `part` is not as above; what `write` throws; reduced::IoError naming the .pvd if
  ///         it cannot be rewritten.
  const PvdEntry& add(double time, std::string_view part, const DatasetWriter& write);

  /// The output directory given to the constructor.
  const std::filesystem::path& directory() const noexcept { return m_directory; }
  /// The collection file, `directory/name.pvd`.
  const std::filesystem::path& file() const noexcept { return m_file; }
  /// Every dataset added, in order.
  const std::vector<PvdEntry>& entries() const noexcept { return m_entries; }

 private:
  /// What add() needs of a part's previous datasets.
  struct PartHistory {
    std::int64_t count = 0;
    double last_time = 0.0;
  };

  void write_collection() const;

  std::filesystem::path m_directory;
  std::string m_name;
  std::filesystem::path m_file;
  std::vector<PvdEntry> m_entries;
  std::map<std::string, PartHistory, std::less<>> m_parts;
  std::string m_dataset_lines;  // the DataSet elements of m_entries, as written
};

}  // namespace khz::series
