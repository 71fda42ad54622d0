#pragma once
// Where scene preparation keeps what it computed: one file per product, named by the content key
// of exactly the inputs it depends on, so a second run reads instead of computing and a changed
// parameter recomputes only what depends on it (issue 9, "model only what a scene needs").

#include <chrono>
#include <filesystem>
#include <functional>
#include <khz/reduced/errors.hpp>
#include <khz/scene/export.hpp>
#include <string>
#include <vector>

namespace khz::scene {

/// A directory of prepared products, each stored as `<directory>/<name>-<key>.<extension>`.
///
/// A product is written to a temporary file in the same directory
/// (`<file>.partial-<host>-<process id>`) and renamed into place, so an interrupted or failed
/// computation never leaves a file that looks complete, and processes sharing the directory
/// (the ranks of an MPI job, on one host or several) never write the same file. A failed
/// computation removes its temporary file; one left by a process that died (killed, out of
/// memory) is removed when a ProductCache next opens the directory on the same host. A product file
/// that exists is read, and its reader checks it (the binary formats carry a checksum); one the
/// reader rejects as damaged is never trusted: it is computed again and replaced, and the record
/// says why.
/// Not thread-safe; one ProductCache per preparing thread.
class KHZ_SCENE_API ProductCache {
 public:
  /// What fetch() did for one product.
  struct Record {
    std::string name;            ///< e.g. "distance_field" (what prepare_scene() names it).
    std::filesystem::path file;  ///< Where the product is stored.
    bool computed = false;       ///< false: read from the cache.
    double seconds = 0.0;        ///< Wall time of the computation (and its write) or the read.
    /// Why the file that was there could not be used (the reader's message; then computed is
    /// true), or empty.
    std::string damaged;
  };

  /// Uses (and creates, with its parents) `directory`, and removes the temporary files that
  /// processes of this host left there when they died.
  /// @throws khz::reduced::IoError naming the directory if it cannot be created.
  explicit ProductCache(std::filesystem::path directory);

  const std::filesystem::path& directory() const noexcept { return m_directory; }

  /// The file a product with this name, key and extension is stored in. The name is reduced to
  /// letters, digits, '-' and '_' (others become '_'), so any object name is safe in a path.
  std::filesystem::path file(const std::string& name, const std::string& key,
                             const std::string& extension) const;

  /// The product: read with `read(file)` if its file exists and `read` accepts it, otherwise
  /// computed with `compute()`, written with `write(product, temporary)` and renamed into place
  /// (over a file `read` rejected with a khz::reduced::ParseError). Records what happened
  /// (records()).
  /// @throws what read (other than ParseError), compute or write throw (the cache keeps no
  ///         partial file); khz::reduced::IoError if the rename fails.
  template <typename Product>
  Product fetch(const std::string& name, const std::string& key, const std::string& extension,
                const std::function<Product(const std::filesystem::path&)>& read,
                const std::function<Product()>& compute,
                const std::function<void(const Product&, const std::filesystem::path&)>& write) {
    const std::filesystem::path target = file(name, key, extension);
    const auto start = std::chrono::steady_clock::now();
    std::string damaged;
    if (std::filesystem::exists(target)) {
      try {
        Product product = read(target);
        record(name, target, false, start, {});
        return product;
      } catch (const reduced::ParseError& error) {
        damaged = error.what();  // cut short, a flipped bit, another version: computed anew
      }
    }
    Product product = compute();
    const std::filesystem::path temporary = temporary_file(target);
    try {
      write(product, temporary);
      commit(temporary, target);
    } catch (...) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw;
    }
    record(name, target, true, start, std::move(damaged));
    return product;
  }

  /// Every fetch() so far, in order.
  const std::vector<Record>& records() const noexcept { return m_records; }
  /// How many of records() were computed rather than read.
  int computed_count() const noexcept;

 private:
  std::filesystem::path temporary_file(const std::filesystem::path& target) const;
  static void commit(const std::filesystem::path& temporary, const std::filesystem::path& target);
  void record(const std::string& name, const std::filesystem::path& file, bool computed,
              std::chrono::steady_clock::time_point start, std::string damaged);

  std::filesystem::path m_directory;
  std::vector<Record> m_records;
};

}  // namespace khz::scene
