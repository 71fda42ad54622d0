#include <khz/contact/io/distance_field_vti.hpp>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <ostream>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace khz::contact {
namespace {

/// Shortest text that reads back as the same value.
template <typename T>
std::string number(T value) {
  std::array<char, 32> text;
  const auto result = std::to_chars(text.data(), text.data() + text.size(), value);
  return std::string(text.data(), result.ptr);
}

/// Base64 (RFC 4648) of a byte stream fed in pieces, written to `out` on one line: VTK's reader
/// decodes the characters between the tags without skipping line breaks.
class Base64Writer {
 public:
  explicit Base64Writer(std::ostream& out) : m_out(out) {}

  void write(std::span<const unsigned char> bytes) {
    for (const unsigned char byte : bytes) {
      m_group[m_pending++] = byte;
      if (m_pending == 3) emit(3);
    }
  }
  /// Pads and writes the last group.
  void finish() {
    if (m_pending > 0) emit(m_pending);
    m_out << '\n';
  }

 private:
  void emit(int count) {
    static constexpr char alphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int i = count; i < 3; ++i) m_group[i] = 0;
    const std::uint32_t bits =
        (std::uint32_t{m_group[0]} << 16) | (std::uint32_t{m_group[1]} << 8) | m_group[2];
    char quad[4];
    for (int i = 0; i < 4; ++i) quad[i] = alphabet[(bits >> (18 - 6 * i)) & 63];
    for (int i = count + 1; i < 4; ++i) quad[i] = '=';
    m_out.write(quad, 4);
    m_pending = 0;
  }

  std::ostream& m_out;
  unsigned char m_group[3] = {};
  int m_pending = 0;
};

void write_vti(std::ostream& out, const DistanceGrid& grid, VtiEncoding encoding) {
  const GridGeometry& g = grid.geometry();
  const std::string name = grid.is_signed() ? "signed_distance" : "distance";
  const std::string extent = "0 " + std::to_string(g.cells) + " 0 " + std::to_string(g.cells) +
                             " 0 " + std::to_string(g.cells);
  const auto values = grid.values();
  float low = values[0], high = values[0];
  for (const float value : values) {
    low = std::min(low, value);
    high = std::max(high, value);
  }
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\""
      << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian")
      << "\" header_type=\"UInt64\">\n"
      << "  <ImageData WholeExtent=\"" << extent << "\" Origin=\"" << number(g.origin.x()) << ' '
      << number(g.origin.y()) << ' ' << number(g.origin.z()) << "\" Spacing=\"" << number(g.spacing)
      << ' ' << number(g.spacing) << ' ' << number(g.spacing) << "\">\n"
      << "    <Piece Extent=\"" << extent << "\">\n"
      << "      <PointData Scalars=\"" << name << "\">\n"
      << "        <DataArray type=\"Float32\" Name=\"" << name << "\" format=\""
      << (encoding == VtiEncoding::base64 ? "binary" : "ascii") << "\" RangeMin=\"" << number(low)
      << "\" RangeMax=\"" << number(high) << "\">\n";
  if (encoding == VtiEncoding::base64) {
    // One base64 stream: the array's byte count (UInt64), then the values.
    Base64Writer base64(out);
    const std::uint64_t count = values.size() * sizeof(float);
    base64.write(std::span(reinterpret_cast<const unsigned char*>(&count), sizeof(count)));
    base64.write(std::span(reinterpret_cast<const unsigned char*>(values.data()),
                           values.size() * sizeof(float)));
    base64.finish();
  } else {
    const auto per_row = static_cast<std::size_t>(g.nodes_per_axis());
    for (std::size_t index = 0; index < values.size(); ++index) {
      out << number(values[index]) << ((index + 1) % per_row == 0 ? '\n' : ' ');
    }
  }
  out << "        </DataArray>\n"
      << "      </PointData>\n"
      << "      <CellData>\n"
      << "      </CellData>\n"
      << "    </Piece>\n"
      << "  </ImageData>\n"
      << "</VTKFile>\n";
}

}  // namespace

std::string format_distance_field_vti(const DistanceGrid& grid, VtiEncoding encoding) {
  std::ostringstream out;
  write_vti(out, grid, encoding);
  return std::move(out).str();
}

void write_distance_field_vti(const std::filesystem::path& file, const DistanceGrid& grid,
                              VtiEncoding encoding) {
  const std::filesystem::path directory =
      file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  // Appended piece by piece: GCC 12 at -O3 mistakes a chain of string + for an overlapping
  // memcpy (-Wrestrict false positive).
  std::string name = ".";
  name.append(file.filename().string())
      .append(".tmp-")
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(std::random_device{}()));
  const std::filesystem::path temporary = directory / name;
  const auto fail = [&](const std::string& what) {
    const std::string reason = errno != 0 ? std::strerror(errno) : "unknown error";
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw IoError(file.string() + ": " + what + ": " + reason);
  };
  errno = 0;
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) fail("cannot create a temporary file in " + directory.string());
    std::vector<char> buffer(std::size_t{1} << 20);
    out.rdbuf()->pubsetbuf(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    write_vti(out, grid, encoding);
    out.flush();
    if (!out) fail("write failed");
  }
  std::error_code error;
  std::filesystem::rename(temporary, file, error);
  if (error) {
    errno = error.value();
    fail("cannot rename " + temporary.filename().string() + " into place");
  }
}

}  // namespace khz::contact
