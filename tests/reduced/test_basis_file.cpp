#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <random>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

/// 3×1×1 cells of six tetrahedra: 16 vertices.
VolumeMesh box() { return box_tet_mesh({0, 0, 0}, {0.3, 0.1, 0.1}, {3, 1, 1}); }

/// A basis for box() with awkward values: subnormals, −0.0, extremes, random bits.
Basis random_basis(const VolumeMesh& mesh, Eigen::Index r) {
  std::mt19937_64 random(42);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Basis basis;
  basis.vectors.resize(3 * mesh.num_vertices(), r);
  for (Eigen::Index k = 0; k < basis.vectors.size(); ++k) basis.vectors.data()[k] = uniform(random);
  if (r > 0) {
    basis.vectors(0, 0) = -0.0;
    basis.vectors(1, 0) = std::numeric_limits<double>::denorm_min();
    basis.vectors(2, 0) = std::numeric_limits<double>::max();
    basis.vectors(3, 0) = -std::numeric_limits<double>::min();
  }
  basis.fixed_vertices = {0, 4, 8, 12};
  basis.recipe = "modal derivatives: k=3 modes, mass PCA to r=" + std::to_string(r) + " (µ ≈ 1)";
  return basis;
}

bool bitwise_equal(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * 8) == 0;
}

/// The single tetrahedron of the committed version-1 file tests/data/basis/tet_v1.khzbasis.
VolumeMesh golden_mesh() {
  VolumeMesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 0.5, 0, 0, 0, 0.25, 0, 0, 0, 2;
  mesh.elements.resize(1, 4);
  mesh.elements << 0, 1, 2, 3;
  return mesh;
}

Basis golden_basis() {
  Basis basis;
  basis.vectors.resize(12, 2);
  for (int i = 0; i < 12; ++i) {
    basis.vectors(i, 0) = (i + 1) / 8.0;
    basis.vectors(i, 1) = i % 2 == 0 ? -0.5 : 0.25;
  }
  basis.vectors.row(0).setZero();  // vertex 0 is fixed: its rows are zero
  basis.vectors.row(1).setZero();
  basis.vectors.row(2).setZero();
  basis.fixed_vertices = {0};
  basis.recipe = "golden test basis, format version 1";
  return basis;
}

void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

/// The bytes of a valid basis file for box(), written once.
const std::string& valid_bytes() {
  static const std::string bytes = [] {
    const std::filesystem::path file = test::scratch_file("valid.khzbasis");
    write_basis(file, random_basis(box(), 3), box());
    return test::read_bytes(file);
  }();
  return bytes;
}

/// A container in the basis format with a hand-made payload: a forged file whose checksum is
/// right but whose values are not.
class ForgedBasis {
 public:
  ForgedBasis() : m_writer(basis_file_format) {}
  /// The header values read_basis() expects for box(), then whatever the test adds.
  ForgedBasis& valid_header(std::uint64_t n = 16, std::uint64_t r = 1) {
    m_writer.write_u64(mesh_fingerprint(box()));
    m_writer.write_u64(n);
    m_writer.write_u64(r);
    m_writer.write_string("forged");
    return *this;
  }
  ContainerWriter& writer() { return m_writer; }
  std::filesystem::path file() {
    const std::filesystem::path path = test::scratch_file("forged.khzbasis");
    write_bytes(path, m_writer.bytes());  // no need for write_file's fsync here
    return path;
  }

 private:
  ContainerWriter m_writer;
};

// ---- Round trips ----------------------------------------------------------------------------

TEST(BasisFile, RoundTripsBitExactly) {
  const VolumeMesh mesh = box();
  const Basis basis = random_basis(mesh, 5);
  const std::filesystem::path file = test::scratch_file("basis.khzbasis");
  write_basis(file, basis, mesh);
  const Basis read = read_basis(file, mesh);
  EXPECT_TRUE(bitwise_equal(read.vectors, basis.vectors));
  EXPECT_EQ(read.fixed_vertices, basis.fixed_vertices);
  EXPECT_EQ(read.recipe, basis.recipe);
  EXPECT_EQ(std::filesystem::file_size(file),
            20 + 24 + 8 + basis.recipe.size() + 8 + 4 * 4 + 16 + 48 * 5 * 8 + 8);
}

TEST(BasisFile, RoundTripsAnEmptyBasis) {
  const VolumeMesh mesh = box();
  Basis basis;
  basis.vectors.resize(48, 0);
  const std::filesystem::path file = test::scratch_file("empty.khzbasis");
  write_basis(file, basis, mesh);
  const Basis read = read_basis(file, mesh);
  EXPECT_EQ(read.vectors.rows(), 48);
  EXPECT_EQ(read.size(), 0);
  EXPECT_TRUE(read.fixed_vertices.empty());
  EXPECT_TRUE(read.recipe.empty());
}

TEST(BasisFile, OverwritesAnExistingFile) {
  const VolumeMesh mesh = box();
  const std::filesystem::path file = test::scratch_file("twice.khzbasis");
  write_basis(file, random_basis(mesh, 4), mesh);
  write_basis(file, random_basis(mesh, 2), mesh);
  EXPECT_EQ(read_basis(file, mesh).size(), 2);
}

TEST(BasisFile, InfoReadsTheHeaderWithoutAMesh) {
  const VolumeMesh mesh = box();
  const Basis basis = random_basis(mesh, 3);
  const std::filesystem::path file = test::scratch_file("info.khzbasis");
  write_basis(file, basis, mesh);
  const BasisFileInfo info = read_basis_info(file);
  EXPECT_EQ(info.format_version, 1u);
  EXPECT_EQ(info.fingerprint, mesh_fingerprint(mesh));
  EXPECT_EQ(info.num_vertices, 16);
  EXPECT_EQ(info.size, 3);
  EXPECT_EQ(info.num_fixed_vertices, 4);
  EXPECT_EQ(info.recipe, basis.recipe);
  EXPECT_EQ(info.file_bytes, std::filesystem::file_size(file));
}

// ---- Format stability -------------------------------------------------------------------------

TEST(BasisFile, WritesTheCommittedVersion1FileByteForByte) {
  // tests/data/basis/tet_v1.khzbasis was written by the first implementation. If this fails,
  // the format changed: bump basis_file_format.version and keep reading version 1 instead.
  const std::filesystem::path file = test::scratch_file("tet_v1.khzbasis");
  write_basis(file, golden_basis(), golden_mesh());
  EXPECT_EQ(test::read_bytes(file), test::read_bytes(test::test_file("basis/tet_v1.khzbasis")))
      << "new bytes in " << file;
}

TEST(BasisFile, ReadsTheCommittedVersion1File) {
  const Basis basis = read_basis(test::test_file("basis/tet_v1.khzbasis"), golden_mesh());
  EXPECT_TRUE(bitwise_equal(basis.vectors, golden_basis().vectors));
  EXPECT_EQ(basis.fixed_vertices, std::vector<int>{0});
  EXPECT_EQ(basis.recipe, "golden test basis, format version 1");
}

// ---- The wrong mesh ---------------------------------------------------------------------------

TEST(BasisFile, RejectsADifferentMeshShowingBothFingerprints) {
  const VolumeMesh mesh = box();
  const std::filesystem::path file = test::scratch_file("basis.khzbasis");
  write_basis(file, random_basis(mesh, 2), mesh);
  const VolumeMesh other = box_tet_mesh({0, 0, 0}, {0.3, 0.1, 0.1}, {2, 1, 1});
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { read_basis(file, other); },
      file.string() + ": the basis belongs to a different mesh: it was computed on a mesh with " +
          "fingerprint " + fingerprint_text(mesh_fingerprint(mesh)) +
          " and 16 vertices, this mesh has fingerprint " +
          fingerprint_text(mesh_fingerprint(other)) + " and 12 vertices"));
}

TEST(BasisFile, RejectsAMeshWithOneVertexMovedByOneUlp) {
  const VolumeMesh mesh = box();
  const std::filesystem::path file = test::scratch_file("basis.khzbasis");
  write_basis(file, random_basis(mesh, 2), mesh);
  VolumeMesh moved = mesh;
  moved.vertices(5, 2) = std::nextafter(moved.vertices(5, 2), 1.0);
  EXPECT_TRUE(test::throws_with_message<Error>([&] { read_basis(file, moved); },
                                               "the basis belongs to a different mesh"));
}

// ---- Invalid bases are not written ------------------------------------------------------------

TEST(BasisFile, RefusesToWriteInvalidBases) {
  const VolumeMesh mesh = box();
  const std::filesystem::path file = test::scratch_file("invalid.khzbasis");
  const std::string prefix = file.string() + ": cannot write basis: ";
  struct Case {
    const char* name;
    void (*edit)(Basis&);
    std::string message;
  };
  const Case cases[] = {
      {"rows", [](Basis& b) { b.vectors.conservativeResize(45, Eigen::NoChange); },
       "U has 45 rows, expected 3·16 = 48 (3 per mesh vertex)"},
      {"nan", [](Basis& b) { b.vectors(7, 1) = std::nan(""); }, "U(7, 1) = nan is not finite"},
      {"inf", [](Basis& b) { b.vectors(0, 2) = -INFINITY; }, "U(0, 2) = -inf is not finite"},
      {"range",
       [](Basis& b) {
         b.fixed_vertices = {3, 16};
       },
       "fixed vertex 16 (entry 1) is out of range [0, 16)"},
      {"negative", [](Basis& b) { b.fixed_vertices = {-1}; },
       "fixed vertex -1 (entry 0) is out of range [0, 16)"},
      {"unsorted",
       [](Basis& b) {
         b.fixed_vertices = {4, 2};
       },
       "fixed vertices must be sorted and distinct: entry 1 is 2 after 4"},
      {"repeated",
       [](Basis& b) {
         b.fixed_vertices = {2, 2};
       },
       "fixed vertices must be sorted and distinct: entry 1 is 2 after 2"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Basis basis = random_basis(mesh, 3);
    c.edit(basis);
    EXPECT_TRUE(test::throws_with_message<Error>([&] { write_basis(file, basis, mesh); },
                                                 prefix + c.message));
    EXPECT_FALSE(std::filesystem::exists(file));
  }
}

TEST(BasisFile, WriteFailureNamesThePath) {
  const std::filesystem::path file = test::scratch_file("no_such_dir") / "basis.khzbasis";
  EXPECT_TRUE(test::throws_with_message<IoError>(
      [&] { write_basis(file, random_basis(box(), 1), box()); },
      file.string() + ": cannot create a temporary file in " + file.parent_path().string() +
          ": No such file or directory"));
}

// ---- Damaged files ----------------------------------------------------------------------------

/// Writes `bytes` to a scratch file and checks read_basis() rejects it with `message` (which
/// is checked after "<file>: ").
::testing::AssertionResult rejected(const std::string& bytes, const std::string& message) {
  const std::filesystem::path file = test::scratch_file("damaged.khzbasis");
  write_bytes(file, bytes);
  auto result =
      test::throws_with_message([&] { read_basis(file, box()); }, file.string() + ": " + message);
  if (!result) return result;
  // read_basis_info() checks the same envelope.
  return test::throws_with_message([&] { read_basis_info(file); }, file.string() + ": " + message);
}

TEST(BasisFile, RejectsTruncationAtEveryLevel) {
  const std::string bytes = valid_bytes();
  const std::string size = std::to_string(bytes.size());
  EXPECT_TRUE(rejected("",
                       "byte 0: file ends early: expected the magic \"KHZBASIS\" (8 bytes, "
                       "0 left)"));
  EXPECT_TRUE(rejected(bytes.substr(0, 5),
                       "byte 0: file ends early: expected the magic "
                       "\"KHZBASIS\" (8 bytes, 5 left)"));
  EXPECT_TRUE(rejected(bytes.substr(0, 10),
                       "byte 8: file ends early: expected the format version (4 bytes, 2 left)"));
  EXPECT_TRUE(rejected(bytes.substr(0, 19),
                       "byte 12: file ends early: expected the file length (8 bytes, 7 left)"));
  for (const std::size_t cut :
       {std::size_t{20}, std::size_t{60}, bytes.size() / 2, bytes.size() - 8, bytes.size() - 1}) {
    SCOPED_TRACE(cut);
    EXPECT_TRUE(rejected(bytes.substr(0, cut), "byte " + std::to_string(cut) +
                                                   ": file ends early: the header declares " +
                                                   size + " bytes, the file has " +
                                                   std::to_string(cut) + " (truncated?)"));
  }
}

TEST(BasisFile, RejectsAnyFlippedByteByTheChecksum) {
  const std::string bytes = valid_bytes();
  const std::string at = "byte " + std::to_string(bytes.size() - 8) + ": ";
  // A payload byte in the fingerprint, the recipe, the fixed vertices and U, and the checksum.
  for (const std::size_t offset : {std::size_t{21}, std::size_t{55}, std::size_t{130},
                                   bytes.size() - 100, bytes.size() - 9, bytes.size() - 1}) {
    SCOPED_TRACE(offset);
    std::string damaged = bytes;
    damaged[offset] = static_cast<char>(damaged[offset] ^ 0x10);
    EXPECT_TRUE(rejected(damaged, at + "checksum mismatch: file is corrupted (stored 0x"));
  }
}

TEST(BasisFile, RejectsOtherFilesByTheirMagic) {
  std::string bytes = valid_bytes();
  bytes[3] = 'b';
  EXPECT_TRUE(rejected(bytes,
                       "byte 0: not a Kilohertz basis file (the file starts with "
                       "\"KHZbASIS\", expected \"KHZBASIS\")"));
  EXPECT_TRUE(rejected("ply\nformat ascii 1.0\n",
                       "byte 0: not a Kilohertz basis file (the file starts with "
                       "\"ply\\x0aform\", expected \"KHZBASIS\")"));
  EXPECT_TRUE(rejected("KHZ", "byte 0: file ends early: expected the magic"));
  EXPECT_TRUE(rejected("KHZMODEL", "byte 0: not a Kilohertz basis file"));
}

TEST(BasisFile, RejectsFutureAndZeroVersions) {
  std::string bytes = valid_bytes();
  bytes[8] = 2;  // the version is checked before the checksum, which a newer format may change
  EXPECT_TRUE(rejected(bytes, "byte 8: written by a newer version 2; this build reads up to 1"));
  bytes[8] = 0;
  bytes[11] = 1;  // 2^24
  EXPECT_TRUE(rejected(bytes,
                       "byte 8: written by a newer version 16777216; this build reads "
                       "up to 1"));
  bytes[11] = 0;
  EXPECT_TRUE(rejected(bytes, "byte 8: invalid format version 0"));
}

TEST(BasisFile, RejectsTrailingBytesAndImpossibleLengths) {
  const std::string bytes = valid_bytes();
  const std::string size = std::to_string(bytes.size());
  EXPECT_TRUE(rejected(bytes + "junk", "byte " + size +
                                           ": 4 bytes after the end of the file (the "
                                           "header declares " +
                                           size + " bytes)"));
  std::string short_length = bytes;
  short_length[12] = 27;
  std::memset(short_length.data() + 13, 0, 7);
  EXPECT_TRUE(rejected(short_length,
                       "byte 12: the header declares a file length of 27 bytes, "
                       "less than the 28 of an empty container"));
  std::string huge_length = bytes;
  std::memset(huge_length.data() + 12, 0xff, 8);
  EXPECT_TRUE(rejected(huge_length, "byte " + size +
                                        ": file ends early: the header declares "
                                        "18446744073709551615 bytes, the file has " +
                                        size));
}

// ---- Forged files: right checksum, wrong values --------------------------------------------

TEST(BasisFile, RejectsAbsurdSizeFieldsWithoutAllocating) {
  const std::uint64_t huge = std::uint64_t{1} << 40;
  struct Case {
    const char* name;
    void (*forge)(ForgedBasis&);
    const char* message;
  };
  const Case cases[] = {
      {"vertex count",
       [](ForgedBasis& f) {
         f.writer().write_u64(mesh_fingerprint(box()));
         f.writer().write_u64(huge);
       },
       "byte 28: vertex count 1099511627776 exceeds the limit of 715827882"},
      {"basis size",
       [](ForgedBasis& f) {
         f.writer().write_u64(mesh_fingerprint(box()));
         f.writer().write_u64(16);
         f.writer().write_u64(huge);
       },
       "byte 36: basis size 1099511627776 exceeds the limit of 2147483647"},
      {"recipe length",
       [](ForgedBasis& f) {
         f.writer().write_u64(mesh_fingerprint(box()));
         f.writer().write_u64(16);
         f.writer().write_u64(1);
         f.writer().write_u64(huge);
       },
       "byte 44: the recipe: 1099511627776 bytes do not fit in the 0 bytes that remain"},
      {"fixed vertex count",
       [](ForgedBasis& f) {
         f.valid_header();
         f.writer().write_u64(huge);
         f.writer().write_u64(0);
       },
       "byte 58: the fixed vertices: 1099511627776 items of 4 bytes do not fit in the 8 bytes "
       "that remain"},
      {"matrix rows",
       [](ForgedBasis& f) {
         f.valid_header();
         f.writer().write_ints({});
         f.writer().write_u64(huge);
         f.writer().write_u64(1);
       },
       "byte 66: the basis matrix U: 1099511627776×1 exceeds the dimension limit of 2147483647"},
      {"matrix entries",
       [](ForgedBasis& f) {
         f.valid_header();
         f.writer().write_ints({});
         f.writer().write_u64(48);
         f.writer().write_u64(2000000000);
       },
       "byte 66: the basis matrix U: 48×2000000000 entries of 8 bytes do not fit in the 0 "
       "bytes that remain"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    ForgedBasis forged;
    c.forge(forged);
    const std::filesystem::path file = forged.file();
    test::largest_allocation = 0;
    EXPECT_TRUE(test::throws_with_message([&] { read_basis(file, box()); },
                                          file.string() + ": " + c.message));
    EXPECT_LT(test::largest_allocation.load(), std::size_t{1} << 20);
  }
}

TEST(BasisFile, RejectsInconsistentValuesAtTheirOffsets) {
  struct Case {
    const char* name;
    void (*forge)(ForgedBasis&);
    const char* message;
  };
  const Case cases[] = {
      {"fixed vertex out of range",
       [](ForgedBasis& f) {
         f.valid_header();
         f.writer().write_ints(std::vector<int>{1, 16});
         f.writer().write_matrix(Eigen::MatrixXd::Zero(48, 1));
       },
       "byte 70: fixed vertex 16 (entry 1) is out of range [0, 16)"},
      {"unsorted fixed vertices",
       [](ForgedBasis& f) {
         f.valid_header();
         f.writer().write_ints(std::vector<int>{5, 3});
         f.writer().write_matrix(Eigen::MatrixXd::Zero(48, 1));
       },
       "byte 70: fixed vertices must be sorted and distinct: entry 1 is 3 after 5"},
      {"U shape",
       [](ForgedBasis& f) {
         f.valid_header();
         f.writer().write_ints({});
         f.writer().write_matrix(Eigen::MatrixXd::Zero(47, 1));
       },
       "byte 66: U is 47×1, expected 48×1 (3n × r from the header)"},
      {"r mismatch",
       [](ForgedBasis& f) {
         f.valid_header(16, 2);
         f.writer().write_ints({});
         f.writer().write_matrix(Eigen::MatrixXd::Zero(48, 1));
       },
       "byte 66: U is 48×1, expected 48×2 (3n × r from the header)"},
      {"non-finite entry",
       [](ForgedBasis& f) {
         f.valid_header();
         f.writer().write_ints({});
         Eigen::MatrixXd u = Eigen::MatrixXd::Zero(48, 1);
         u(10, 0) = std::nan("");
         f.writer().write_matrix(u);
       },
       "byte 162: U(10, 0) = nan is not finite"},
      {"vertex count",
       [](ForgedBasis& f) {
         f.valid_header(17);
         f.writer().write_ints({});
         f.writer().write_matrix(Eigen::MatrixXd::Zero(51, 1));
       },
       "byte 28: vertex count 17 differs from the mesh's 16 although the fingerprints match"},
      {"unread bytes",
       [](ForgedBasis& f) {
         f.valid_header();
         f.writer().write_ints({});
         f.writer().write_matrix(Eigen::MatrixXd::Zero(48, 1));
         f.writer().write_u32(0);
       },
       "byte 466: 4 unread bytes after the basis matrix U"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    ForgedBasis forged;
    c.forge(forged);
    const std::filesystem::path file = forged.file();
    EXPECT_TRUE(test::throws_with_message([&] { read_basis(file, box()); },
                                          file.string() + ": " + c.message));
  }
}

// ---- The committed malformed corpus ---------------------------------------------------------

TEST(BasisFile, RejectsTheMalformedCorpus) {
  // Made from tests/data/basis/tet_v1.khzbasis (315 bytes) by make_binary_cases.py.
  const test::MalformedFile cases[] = {
      {"empty.khzbasis",
       "empty.khzbasis: byte 0: file ends early: expected the magic \"KHZBASIS\""},
      {"not_basis.khzbasis", "not_basis.khzbasis: byte 0: not a Kilohertz basis file"},
      {"future_version.khzbasis",
       "future_version.khzbasis: byte 8: written by a newer version 2; this build reads up to 1"},
      {"truncated_header.khzbasis",
       "truncated_header.khzbasis: byte 12: file ends early: expected the file length (8 bytes, "
       "4 left)"},
      {"truncated.khzbasis",
       "truncated.khzbasis: byte 200: file ends early: the header declares 315 bytes, the file "
       "has 200 (truncated?)"},
      {"flipped_byte.khzbasis",
       "flipped_byte.khzbasis: byte 307: checksum mismatch: file is corrupted"},
      {"trailing_bytes.khzbasis",
       "trailing_bytes.khzbasis: byte 315: 4 bytes after the end of the file"},
  };
  test::expect_corpus_rejected("malformed/basis", cases, [](const std::filesystem::path& file) {
    read_basis(file, golden_mesh());
  });
}

}  // namespace
}  // namespace khz::reduced
