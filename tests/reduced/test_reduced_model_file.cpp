#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

// ---- A small two-material model -------------------------------------------------------------

/// 2×1×1 cells of six tetrahedra (12 vertices): x < 0.1 is group 0, the rest group 1.
VolumeMesh box() {
  VolumeMesh mesh = box_tet_mesh({0, 0, 0}, {0.2, 0.1, 0.1}, {2, 1, 1});
  mesh.element_groups.resize(mesh.num_elements());
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    double x = 0;
    for (Eigen::Index a = 0; a < 4; ++a) x += mesh.vertices(mesh.elements(e, a), 0);
    mesh.element_groups[e] = x / 4 < 0.1 ? 0 : 1;
  }
  return mesh;
}

/// A random symmetric positive definite Voigt matrix (Pa): a general anisotropic material.
VoigtMatrix anisotropic_elasticity() {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  VoigtMatrix a;
  for (Eigen::Index i = 0; i < a.size(); ++i) a(i) = entry(random);
  return 2e5 * (a.transpose() * a + 3.0 * VoigtMatrix::Identity());
}

/// A random basis of r vectors, zero at the clamped vertices x = 0.
Basis random_basis(const VolumeMesh& mesh, Eigen::Index r) {
  std::mt19937 random(11);
  std::normal_distribution<double> entry(0.0, 0.1);
  Basis basis;
  basis.vectors.resize(3 * mesh.num_vertices(), r);
  for (Eigen::Index i = 0; i < basis.vectors.size(); ++i) basis.vectors(i) = entry(random);
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.vertices(v, 0) == 0.0) {
      basis.vectors.middleRows<3>(3 * v).setZero();
      basis.fixed_vertices.push_back(static_cast<int>(v));
    }
  }
  basis.recipe = "random test basis, r = " + std::to_string(r) + " (µ ≈ 0.1)";
  return basis;
}

/// Precomputed on box() with an StVK and a general group, r = 3; then, as a tuned model would
/// be, with changed materials and integrator defaults.
const ReducedModel& model() {
  static const ReducedModel tuned = [] {
    const FemModel fem(box(), {Material::stvk_lame({4e5, 3e5}, 1000.0),
                               Material::general(anisotropic_elasticity(), 1500.0)});
    ReducedModel model = ReducedModel::precompute(fem, random_basis(box(), 3));
    model.set_lame(0, {9e5, 1e5 / 3});
    model.set_elasticity_scale(1, 2.5);
    model.set_density(1, 700.0 / 3);
    model.set_defaults({{1.0 / 3000, 0.3, 0.6, 0.1, 1e-4}, 3, 1e-7});
    return model;
  }();
  return tuned;
}

template <typename Matrix>
bool bitwise_equal(const Matrix& a, const Matrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(double)) == 0;
}

bool bitwise_equal(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Checks every value of two models bit for bit, the derived materials included.
void expect_bitwise_equal(const ReducedModel& read, const ReducedModel& written) {
  EXPECT_TRUE(bitwise_equal(read.basis().vectors, written.basis().vectors));
  EXPECT_EQ(read.basis().fixed_vertices, written.basis().fixed_vertices);
  EXPECT_EQ(read.basis().recipe, written.basis().recipe);
  const ReducedIntegratorDefaults &a = read.defaults(), &b = written.defaults();
  EXPECT_TRUE(bitwise_equal(a.newmark.time_step, b.newmark.time_step));
  EXPECT_TRUE(bitwise_equal(a.newmark.beta, b.newmark.beta));
  EXPECT_TRUE(bitwise_equal(a.newmark.gamma, b.newmark.gamma));
  EXPECT_TRUE(bitwise_equal(a.newmark.mass_damping, b.newmark.mass_damping));
  EXPECT_TRUE(bitwise_equal(a.newmark.stiffness_damping, b.newmark.stiffness_damping));
  EXPECT_EQ(a.max_newton_iterations, b.max_newton_iterations);
  EXPECT_TRUE(bitwise_equal(a.newton_tolerance, b.newton_tolerance));
  ASSERT_EQ(read.groups().size(), written.groups().size());
  for (std::size_t g = 0; g < read.groups().size(); ++g) {
    SCOPED_TRACE("group " + std::to_string(g));
    const ReducedMaterialGroup &x = read.groups()[g], &y = written.groups()[g];
    EXPECT_EQ(x.material.is_stvk(), y.material.is_stvk());
    EXPECT_TRUE(bitwise_equal(x.material.elasticity(), y.material.elasticity()));
    EXPECT_TRUE(bitwise_equal(x.material.density(), y.material.density()));
    EXPECT_TRUE(bitwise_equal(x.material.lame().lambda, y.material.lame().lambda));
    EXPECT_TRUE(bitwise_equal(x.material.lame().mu, y.material.lame().mu));
    EXPECT_TRUE(bitwise_equal(x.reference_elasticity, y.reference_elasticity));
    EXPECT_TRUE(bitwise_equal(x.elasticity_scale, y.elasticity_scale));
    ASSERT_EQ(x.parts.size(), y.parts.size());
    for (std::size_t p = 0; p < x.parts.size(); ++p) {
      EXPECT_TRUE(bitwise_equal(x.parts[p].quadratic, y.parts[p].quadratic));
      EXPECT_TRUE(bitwise_equal(x.parts[p].cubic, y.parts[p].cubic));
      EXPECT_TRUE(bitwise_equal(x.parts[p].quartic, y.parts[p].quartic));
    }
    EXPECT_TRUE(bitwise_equal(x.unit_density_mass, y.unit_density_mass));
  }
}

void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

// ---- An independent encoder of the documented format ----------------------------------------

/// The values of a model file in payload order, encoded from the format documentation in
/// reduced_model_file.hpp rather than by the library's writer: a test first checks that both
/// give the same bytes, then forges files whose checksum is right but whose values are not, and
/// knows the offset of every value.
struct Payload {
  struct Part {
    Eigen::MatrixXd k;
    std::vector<double> cubic, quartic;
  };
  struct Group {
    std::uint32_t kind = 0;
    double lambda = 0, mu = 0;  // kind 0
    Eigen::MatrixXd c0;         // kind 1
    double scale = 1;           // kind 1
    double density = 0;
    std::vector<Part> parts;
    Eigen::MatrixXd mass;
  };

  std::uint64_t fingerprint = 0, n = 0, r = 0;
  std::string recipe;
  std::vector<int> fixed;
  Eigen::MatrixXd u;
  double time_step = 0, beta = 0, gamma = 0, alpha = 0, rayleigh_beta = 0;
  std::int32_t j_max = 0;
  double tolerance = 0;
  std::uint64_t group_count = 0;  // normally groups.size()
  std::vector<Group> groups;

  static Payload of(const ReducedModel& model, const VolumeMesh& mesh) {
    Payload p;
    p.fingerprint = mesh_fingerprint(mesh);
    p.n = static_cast<std::uint64_t>(mesh.num_vertices());
    p.r = static_cast<std::uint64_t>(model.dimension());
    p.recipe = model.basis().recipe;
    p.fixed = model.basis().fixed_vertices;
    p.u = model.basis().vectors;
    const ReducedIntegratorDefaults& d = model.defaults();
    p.time_step = d.newmark.time_step;
    p.beta = d.newmark.beta;
    p.gamma = d.newmark.gamma;
    p.alpha = d.newmark.mass_damping;
    p.rayleigh_beta = d.newmark.stiffness_damping;
    p.j_max = d.max_newton_iterations;
    p.tolerance = d.newton_tolerance;
    p.group_count = model.groups().size();
    for (const ReducedMaterialGroup& group : model.groups()) {
      Group g;
      g.kind = group.material.is_stvk() ? 0 : 1;
      g.lambda = group.material.lame().lambda;
      g.mu = group.material.lame().mu;
      g.c0 = group.reference_elasticity;
      g.scale = group.elasticity_scale;
      g.density = group.material.density();
      for (const EnergyPolynomial& part : group.parts) {
        g.parts.push_back({part.quadratic,
                           {part.cubic.data(), part.cubic.data() + part.cubic.size()},
                           {part.quartic.data(), part.quartic.data() + part.quartic.size()}});
      }
      g.mass = group.unit_density_mass;
      p.groups.push_back(std::move(g));
    }
    return p;
  }

  /// One value of the payload: its name (for offsets) and how to write it.
  struct Field {
    std::string name;
    std::function<void(ContainerWriter&)> write;
  };

  /// The payload value by value; names are "r", "U", "group 1 kind", "group 0 part 1 cubic", ...
  std::vector<Field> fields() const {
    std::vector<Field> f;
    f.push_back({"fingerprint", [this](ContainerWriter& w) { w.write_u64(fingerprint); }});
    f.push_back({"n", [this](ContainerWriter& w) { w.write_u64(n); }});
    f.push_back({"r", [this](ContainerWriter& w) { w.write_u64(r); }});
    f.push_back({"recipe", [this](ContainerWriter& w) { w.write_string(recipe); }});
    f.push_back({"fixed", [this](ContainerWriter& w) { w.write_ints(fixed); }});
    f.push_back({"U", [this](ContainerWriter& w) { w.write_matrix(u); }});
    f.push_back({"time step", [this](ContainerWriter& w) {
                   for (const double v : {time_step, beta, gamma, alpha, rayleigh_beta}) {
                     w.write_f64(v);
                   }
                 }});
    f.push_back({"j_max", [this](ContainerWriter& w) { w.write_i32(j_max); }});
    f.push_back({"tolerance", [this](ContainerWriter& w) { w.write_f64(tolerance); }});
    f.push_back({"group count", [this](ContainerWriter& w) { w.write_u64(group_count); }});
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const Group& group = groups[g];
      const std::string name = "group " + std::to_string(g);
      f.push_back({name + " kind", [&group](ContainerWriter& w) { w.write_u32(group.kind); }});
      if (group.kind == 0) {
        f.push_back({name + " lambda", [&group](ContainerWriter& w) {
                       w.write_f64(group.lambda);
                       w.write_f64(group.mu);
                     }});
      } else {
        f.push_back({name + " C0", [&group](ContainerWriter& w) { w.write_matrix(group.c0); }});
        f.push_back({name + " scale", [&group](ContainerWriter& w) { w.write_f64(group.scale); }});
      }
      f.push_back(
          {name + " density", [&group](ContainerWriter& w) { w.write_f64(group.density); }});
      for (std::size_t p = 0; p < group.parts.size(); ++p) {
        const Part& part = group.parts[p];
        const std::string prefix = name + " part " + std::to_string(p);
        f.push_back({prefix + " K", [&part](ContainerWriter& w) { w.write_matrix(part.k); }});
        f.push_back(
            {prefix + " cubic", [&part](ContainerWriter& w) { w.write_doubles(part.cubic); }});
        f.push_back(
            {prefix + " quartic", [&part](ContainerWriter& w) { w.write_doubles(part.quartic); }});
      }
      f.push_back({name + " mass", [&group](ContainerWriter& w) { w.write_matrix(group.mass); }});
    }
    f.push_back({"end", [](ContainerWriter&) {}});
    return f;
  }

  /// The file's bytes; `offsets`, if given, gets the offset at which each field begins.
  std::string bytes(std::map<std::string, std::size_t>* offsets = nullptr) const {
    return bytes_until("", {}, offsets);
  }

  /// The file's bytes up to field `cut`, then what `rest` writes instead of the remainder.
  std::string bytes_until(const std::string& cut, const std::function<void(ContainerWriter&)>& rest,
                          std::map<std::string, std::size_t>* offsets = nullptr) const {
    ContainerWriter w(reduced_model_file_format);
    for (const Field& field : fields()) {
      if (field.name == cut) {
        rest(w);
        break;
      }
      if (offsets != nullptr) (*offsets)[field.name] = w.bytes().size() - container_checksum_bytes;
      field.write(w);
    }
    return w.bytes();
  }
};

/// The bytes of model() written by the library, once.
const std::string& valid_bytes() {
  static const std::string bytes = [] {
    const std::filesystem::path file = test::scratch_file("valid.khzmodel");
    write_reduced_model(file, model(), box());
    return test::read_bytes(file);
  }();
  return bytes;
}

/// Offsets of every value in valid_bytes().
const std::map<std::string, std::size_t>& offsets() {
  static const std::map<std::string, std::size_t> marks = [] {
    std::map<std::string, std::size_t> result;
    Payload::of(model(), box()).bytes(&result);
    return result;
  }();
  return marks;
}

/// "byte <offset>: " of a value of valid_bytes().
std::string at(const std::string& value) {
  return "byte " + std::to_string(offsets().at(value)) + ": ";
}

// ---- Round trips ----------------------------------------------------------------------------

TEST(ReducedModelFile, RoundTripsBitExactly) {
  const std::filesystem::path file = test::scratch_file("model.khzmodel");
  write_reduced_model(file, model(), box());
  const ReducedModel read = read_reduced_model(file, box());
  expect_bitwise_equal(read, model());
  // What is stored and nothing else: writing the model read gives the same bytes.
  const std::filesystem::path again = test::scratch_file("again.khzmodel");
  write_reduced_model(again, read, box());
  EXPECT_EQ(test::read_bytes(again), test::read_bytes(file));
}

TEST(ReducedModelFile, RoundTripsAFreshPrecomputeBitExactly) {
  const FemModel fem(box(), {Material::stvk(2e6, 0.3, 1100.0),
                             Material::general(anisotropic_elasticity(), 1500.0)});
  const ReducedModel fresh = ReducedModel::precompute(fem, random_basis(box(), 2));
  const std::filesystem::path file = test::scratch_file("fresh.khzmodel");
  write_reduced_model(file, fresh, box());
  expect_bitwise_equal(read_reduced_model(file, box()), fresh);
}

TEST(ReducedModelFile, TheDocumentedLayoutIsWhatTheWriterWrites) {
  EXPECT_EQ(Payload::of(model(), box()).bytes(), valid_bytes());
}

TEST(ReducedModelFile, ReadsWithoutTheMesh) {
  const std::filesystem::path file = test::scratch_file("model.khzmodel");
  write_reduced_model(file, model(), box());
  expect_bitwise_equal(read_reduced_model(file), model());
}

TEST(ReducedModelFile, ParsesBytesInMemoryAsTheFileReaderDoes) {
  expect_bitwise_equal(parse_reduced_model(valid_bytes(), "memory"), model());
  std::string damaged = valid_bytes();
  damaged[21] = static_cast<char>(damaged[21] ^ 0x01);
  EXPECT_TRUE(test::throws_with_message<ParseError>([&] { parse_reduced_model(damaged, "memory"); },
                                                    "memory: byte "));
}

TEST(ReducedModelFile, InfoReportsTheFacts) {
  const std::filesystem::path file = test::scratch_file("info.khzmodel");
  write_reduced_model(file, model(), box());
  const ReducedModelFileInfo info = read_reduced_model_info(file);
  EXPECT_EQ(info.basis.format_version, 1u);
  EXPECT_EQ(info.basis.fingerprint, mesh_fingerprint(box()));
  EXPECT_EQ(info.basis.num_vertices, 12);
  EXPECT_EQ(info.basis.size, 3);
  EXPECT_EQ(info.basis.num_fixed_vertices, 4);
  EXPECT_EQ(info.basis.recipe, model().basis().recipe);
  EXPECT_EQ(info.basis.file_bytes, std::filesystem::file_size(file));
  ASSERT_EQ(info.groups.size(), 2u);
  EXPECT_TRUE(info.groups[0].material.is_stvk());
  EXPECT_EQ(info.groups[0].material.lame().lambda, 9e5);
  EXPECT_EQ(info.groups[0].material.lame().mu, 1e5 / 3);
  EXPECT_EQ(info.groups[0].material.density(), 1000.0);
  EXPECT_FALSE(info.groups[1].material.is_stvk());
  EXPECT_EQ(info.groups[1].elasticity_scale, 2.5);
  EXPECT_EQ(info.groups[1].material.elasticity(), model().groups()[1].material.elasticity());
  EXPECT_EQ(info.groups[1].material.density(), 700.0 / 3);
  EXPECT_EQ(info.defaults.newmark.time_step, 1.0 / 3000);
  EXPECT_EQ(info.defaults.newmark.beta, 0.3);
  EXPECT_EQ(info.defaults.newmark.gamma, 0.6);
  EXPECT_EQ(info.defaults.newmark.mass_damping, 0.1);
  EXPECT_EQ(info.defaults.newmark.stiffness_damping, 1e-4);
  EXPECT_EQ(info.defaults.max_newton_iterations, 3);
  EXPECT_EQ(info.defaults.newton_tolerance, 1e-7);
}

// ---- Format stability -------------------------------------------------------------------------

/// Two tetrahedra sharing a face: the mesh of tests/data/model/two_tets_v1.khzmodel.
VolumeMesh golden_mesh() {
  VolumeMesh mesh;
  mesh.vertices.resize(5, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  mesh.elements.resize(2, 4);
  mesh.elements << 0, 1, 2, 3, 1, 2, 3, 4;
  return mesh;
}

/// A hand-made r = 2 model of exactly representable values (so its bytes do not depend on any
/// floating-point computation): an StVK and a general group, vertex 0 fixed.
ReducedModel golden_model() {
  Basis basis;
  basis.vectors.resize(15, 2);
  for (int i = 0; i < 15; ++i) {
    basis.vectors(i, 0) = (i + 1) / 16.0;
    basis.vectors(i, 1) = i % 2 == 0 ? -0.5 : 0.25;
  }
  basis.vectors.topRows<3>().setZero();
  basis.fixed_vertices = {0};
  basis.recipe = "golden test model, format version 1";
  const auto polynomial = [](double base) {
    EnergyPolynomial e;
    e.quadratic.resize(2, 2);
    e.quadratic << 2 * base, base / 2, base / 2, base;
    e.cubic = Eigen::Vector4d(base / 4, -base / 8, 0.0, base / 16);
    e.quartic.resize(5);
    e.quartic << base, base / 2, -base / 4, base / 8, base / 32;
    return e;
  };
  VoigtMatrix c0 = 4e5 * VoigtMatrix::Identity();
  c0(0, 1) = c0(1, 0) = 1.25e5;
  c0(3, 5) = c0(5, 3) = -0.5e5;
  Eigen::Matrix2d mass0, mass1;
  mass0 << 0.5e-3, 0.125e-3, 0.125e-3, 0.25e-3;
  mass1 << 0.25e-3, 0.0, 0.0, 0.5e-3;
  std::vector<ReducedMaterialGroup> groups;
  groups.push_back({Material::stvk_lame({40000, 30000}, 1000),
                    VoigtMatrix::Zero(),
                    1.0,
                    {polynomial(1.0), polynomial(2.0)},
                    mass0});
  groups.push_back({Material::general(2.0 * c0, 500), c0, 2.0, {polynomial(0.5)}, mass1});
  return ReducedModel::from_parts(std::move(basis), std::move(groups),
                                  {{1.0 / 1024, 0.25, 0.5, 0.5, 1.0 / 4096}, 2, 1.0 / 1048576});
}

TEST(ReducedModelFile, WritesTheCommittedVersion1FileByteForByte) {
  // tests/data/model/two_tets_v1.khzmodel was written by the first implementation. If this
  // fails, the format changed: bump reduced_model_file_format.version and keep reading version 1.
  const std::filesystem::path file = test::scratch_file("two_tets_v1.khzmodel");
  write_reduced_model(file, golden_model(), golden_mesh());
  EXPECT_EQ(test::read_bytes(file), test::read_bytes(test::test_file("model/two_tets_v1.khzmodel")))
      << "new bytes in " << file;
}

TEST(ReducedModelFile, ReadsTheCommittedVersion1File) {
  const std::filesystem::path file = test::test_file("model/two_tets_v1.khzmodel");
  expect_bitwise_equal(read_reduced_model(file, golden_mesh()), golden_model());
  expect_bitwise_equal(read_reduced_model(file), golden_model());
}

// ---- The wrong mesh ---------------------------------------------------------------------------

TEST(ReducedModelFile, RejectsADifferentMeshShowingBothFingerprints) {
  const std::filesystem::path file = test::scratch_file("model.khzmodel");
  write_reduced_model(file, model(), box());
  const VolumeMesh other = box_tet_mesh({0, 0, 0}, {0.2, 0.1, 0.1}, {1, 1, 1});
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { read_reduced_model(file, other); },
      file.string() + ": the reduced model belongs to a different mesh: it was computed on a " +
          "mesh with fingerprint " + fingerprint_text(mesh_fingerprint(box())) +
          " and 12 vertices, this mesh has fingerprint " +
          fingerprint_text(mesh_fingerprint(other)) + " and 8 vertices"));
}

// ---- Invalid models are not written -----------------------------------------------------------

TEST(ReducedModelFile, RefusesToWriteAModelThatDoesNotFitTheMesh) {
  // A ReducedModel is valid by construction (precompute and from_parts reject a NaN in U, in a
  // coefficient or in a mass); what can be wrong is its relation to the mesh.
  Basis nan_basis = random_basis(box(), 3);
  nan_basis.vectors(7, 1) = std::nan("");
  EXPECT_THROW((void)ReducedModel::from_parts(nan_basis, model().groups(), {}), Error);

  const std::filesystem::path file = test::scratch_file("invalid.khzmodel");
  const std::string prefix = file.string() + ": cannot write reduced model: ";
  const VolumeMesh smaller = box_tet_mesh({0, 0, 0}, {0.2, 0.1, 0.1}, {1, 1, 1});
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { write_reduced_model(file, model(), smaller); },
      prefix + "U has 36 rows, expected 3·8 = 24 (3 per mesh vertex)"));
  EXPECT_FALSE(std::filesystem::exists(file));

  Basis unsorted = random_basis(box(), 2);
  unsorted.fixed_vertices = {4, 2};
  const FemModel fem(box(), {Material::stvk(2e6, 0.3, 1100.0), Material::stvk(1e6, 0.3, 900.0)});
  const ReducedModel bad_anchors = ReducedModel::precompute(fem, unsorted);
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { write_reduced_model(file, bad_anchors, box()); },
      prefix + "fixed vertices must be sorted and distinct: entry 1 is 2 after 4"));
  EXPECT_FALSE(std::filesystem::exists(file));

  // A failed write leaves an existing file as it was.
  write_reduced_model(file, model(), box());
  EXPECT_THROW(write_reduced_model(file, model(), smaller), Error);
  EXPECT_EQ(test::read_bytes(file), valid_bytes());
}

TEST(ReducedModelFile, WriteFailureNamesThePath) {
  const std::filesystem::path file = test::scratch_file("no_such_dir") / "model.khzmodel";
  EXPECT_TRUE(test::throws_with_message<IoError>(
      [&] { write_reduced_model(file, model(), box()); },
      file.string() + ": cannot create a temporary file in " + file.parent_path().string()));
}

// ---- Damaged files ----------------------------------------------------------------------------

/// Writes `bytes` to a scratch file and checks that read_reduced_model() (with and without the
/// mesh) and read_reduced_model_info() reject it with a ParseError "<file>: <message>...", at
/// byte `offset`.
::testing::AssertionResult rejected(const std::string& bytes, std::size_t offset,
                                    const std::string& message) {
  const std::filesystem::path file = test::scratch_file("damaged.khzmodel");
  write_bytes(file, bytes);
  const std::string expected = file.string() + ": byte " + std::to_string(offset) + ": " + message;
  const std::function<void()> reads[] = {[&] { read_reduced_model(file, box()); },
                                         [&] { read_reduced_model(file); },
                                         [&] { read_reduced_model_info(file); }};
  for (const auto& read : reads) {
    try {
      read();
      return ::testing::AssertionFailure() << "did not throw (expected \"" << expected << "\")";
    } catch (const ParseError& error) {
      if (std::string(error.what()).find(expected) != 0) {
        return ::testing::AssertionFailure()
               << "message \"" << error.what() << "\" does not start with \"" << expected << "\"";
      }
      if (error.byte_offset() != static_cast<std::int64_t>(offset)) {
        return ::testing::AssertionFailure() << "byte_offset() is " << error.byte_offset();
      }
    } catch (const std::exception& error) {
      return ::testing::AssertionFailure() << "threw the wrong type: " << error.what();
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(ReducedModelFile, RejectsOtherFilesByTheirMagic) {
  const std::filesystem::path basis = test::scratch_file("basis.khzbasis");
  write_basis(basis, model().basis(), box());
  EXPECT_TRUE(rejected(test::read_bytes(basis), 0,
                       "not a Kilohertz reduced model file (the file starts with \"KHZBASIS\", "
                       "expected \"KHZMODEL\")"));
  EXPECT_TRUE(
      rejected("", 0, "file ends early: expected the magic \"KHZMODEL\" (8 bytes, 0 left)"));
}

TEST(ReducedModelFile, RejectsTruncation) {
  const std::string bytes = valid_bytes();
  const std::string size = std::to_string(bytes.size());
  EXPECT_TRUE(rejected(bytes.substr(0, 10), 8,
                       "file ends early: expected the format version (4 bytes, 2 left)"));
  for (const std::size_t cut : {std::size_t{20}, offsets().at("group 1 kind"), bytes.size() - 1}) {
    SCOPED_TRACE(cut);
    EXPECT_TRUE(rejected(bytes.substr(0, cut), cut,
                         "file ends early: the header declares " + size + " bytes, the file has " +
                             std::to_string(cut) + " (truncated?)"));
  }
}

TEST(ReducedModelFile, RejectsAnyFlippedByteByTheChecksum) {
  const std::string bytes = valid_bytes();
  for (const std::size_t offset : {std::size_t{21}, offsets().at("time step") + 3,
                                   offsets().at("group 1 C0") + 100, bytes.size() - 20}) {
    SCOPED_TRACE(offset);
    std::string damaged = bytes;
    damaged[offset] = static_cast<char>(damaged[offset] ^ 0x01);
    EXPECT_TRUE(
        rejected(damaged, bytes.size() - 8, "checksum mismatch: file is corrupted (stored 0x"));
  }
}

TEST(ReducedModelFile, RejectsANewerVersion) {
  std::string bytes = valid_bytes();
  bytes[8] = 2;
  EXPECT_TRUE(rejected(bytes, 8, "written by a newer version 2; this build reads up to 1"));
}

// ---- Forged files: right checksum, wrong values --------------------------------------------

struct Forgery {
  const char* name;
  std::function<void(Payload&)> edit;
  std::string value;  // the offsets() key of the value the error points at
  std::size_t plus;   // bytes after that offset
  std::string message;
};

void expect_forgeries_rejected(const std::vector<Forgery>& forgeries) {
  for (const Forgery& forgery : forgeries) {
    SCOPED_TRACE(forgery.name);
    Payload payload = Payload::of(model(), box());
    forgery.edit(payload);
    EXPECT_TRUE(
        rejected(payload.bytes(), offsets().at(forgery.value) + forgery.plus, forgery.message));
  }
}

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

TEST(ReducedModelFile, RejectsInconsistentSizes) {
  expect_forgeries_rejected({
      {"cubic too short", [](Payload& p) { p.groups[0].parts[1].cubic.pop_back(); },
       "group 0 part 1 cubic", 0,
       "group 0's μ part cubic coefficients: 9 coefficients, expected 10 (C(r+2, 3))"},
      {"quartic too long", [](Payload& p) { p.groups[1].parts[0].quartic.push_back(0.0); },
       "group 1 part 0 quartic", 0,
       "group 1's C₀ part quartic coefficients: 16 coefficients, expected 15 (C(r+3, 4))"},
      {"K shape", [](Payload& p) { p.groups[0].parts[0].k.conservativeResize(3, 2); },
       "group 0 part 0 K", 0, "group 0's λ part K is 3×2, expected 3×3 (r × r)"},
      {"mass shape", [](Payload& p) { p.groups[1].mass = Eigen::MatrixXd::Identity(2, 2); },
       "group 1 mass", 0, "group 1's unit-density mass is 2×2, expected 3×3 (r × r)"},
      {"C0 shape", [](Payload& p) { p.groups[1].c0.conservativeResize(5, 6); }, "group 1 C0", 0,
       "group 1's C₀ is 5×6, expected 6×6 (a Voigt matrix)"},
      {"U shape", [](Payload& p) { p.u.conservativeResize(Eigen::NoChange, 2); }, "U", 0,
       "U is 36×2, expected 36×3 (3n × r from the header)"},
      {"r = 0", [](Payload& p) { p.r = 0; }, "r", 0,
       "basis size 0: a reduced model needs at least one vector"},
      {"r too large", [](Payload& p) { p.r = 10001; }, "r", 0,
       "basis size 10001 exceeds the limit of 10000"},
      {"no groups", [](Payload& p) { p.group_count = 0; }, "group count", 0, "no material groups"},
      {"a group missing", [](Payload& p) { p.group_count = 3; }, "end", 0,
       "file ends early: expected group 2's material kind (4 bytes, 0 left)"},
      {"a group too many", [](Payload& p) { p.group_count = 1; }, "group 1 kind", 0,
       std::to_string(offsets().at("end") - offsets().at("group 1 kind")) +
           " unread bytes after the last material group"},
  });
}

TEST(ReducedModelFile, RejectsInvalidValues) {
  expect_forgeries_rejected({
      {"NaN quartic coefficient", [](Payload& p) { p.groups[1].parts[0].quartic[4] = nan; },
       "group 1 part 0 quartic", 8 + 4 * 8,
       "group 1's C₀ part quartic coefficients[4] = nan is not finite"},
      {"infinite K entry", [](Payload& p) { p.groups[0].parts[1].k(1, 2) = -INFINITY; },
       "group 0 part 1 K", 16 + (2 * 3 + 1) * 8, "group 0's μ part K(1, 2) = -inf is not finite"},
      {"NaN in U", [](Payload& p) { p.u(20, 1) = nan; }, "U", 16 + (36 + 20) * 8,
       "U(20, 1) = nan is not finite"},
      {"NaN mass", [](Payload& p) { p.groups[0].mass(0, 0) = nan; }, "group 0 mass", 16,
       "group 0's unit-density mass(0, 0) = nan is not finite"},
      {"asymmetric K", [](Payload& p) { p.groups[0].parts[0].k(0, 1) += 1.0; }, "group 0 part 0 K",
       0, "group 0's λ part: EnergyPolynomial: the quadratic part is not symmetric"},
      {"non-SPD mass",
       [](Payload& p) {
         for (Payload::Group& g : p.groups) g.mass = -g.mass;
       },
       "group count", 0,
       "the material groups do not form a valid model: ReducedModel: the reduced mass is not "
       "positive definite"},
      {"unknown material kind", [](Payload& p) { p.groups[1].kind = 7; }, "group 1 kind", 0,
       "group 1: unknown material kind 7 (0 = StVK, 1 = general)"},
      {"negative shear modulus", [](Payload& p) { p.groups[0].mu = -1.0; }, "group 0 kind", 0,
       "group 0: invalid material: StVK shear modulus mu must be positive and finite, got -1 Pa"},
      {"NaN λ", [](Payload& p) { p.groups[0].lambda = nan; }, "group 0 lambda", 0,
       "group 0's λ = nan is not finite"},
      {"indefinite C0", [](Payload& p) { p.groups[1].c0 = -p.groups[1].c0; }, "group 1 kind", 0,
       "group 1: invalid material: elasticity matrix is not positive definite"},
      {"zero scale", [](Payload& p) { p.groups[1].scale = 0.0; }, "group 1 scale", 0,
       "group 1's elasticity scale s = 0 must be positive"},
      {"zero density", [](Payload& p) { p.groups[1].density = 0.0; }, "group 1 kind", 0,
       "group 1: invalid material: material density must be positive and finite, got 0 kg/m³"},
      {"NaN time step", [](Payload& p) { p.time_step = nan; }, "time step", 0,
       "the default time step = nan is not finite"},
      {"beta out of range", [](Payload& p) { p.beta = 0.75; }, "time step", 0,
       "invalid default integrator parameters: Newmark parameter beta = 0.750000 must be in "
       "[0, 0.5]"},
      {"no Newton iteration", [](Payload& p) { p.j_max = 0; }, "j_max", 0,
       "the default Newton iteration limit is 0, it must be at least 1"},
      {"negative tolerance", [](Payload& p) { p.tolerance = -1e-9; }, "tolerance", 0,
       "the default Newton tolerance is -1e-09, it must be positive"},
      {"unsorted fixed vertices",
       [](Payload& p) {
         p.fixed = {4, 2};
       },
       "fixed", 8 + 4, "fixed vertices must be sorted and distinct: entry 1 is 2 after 4"},
      {"fixed vertex out of range", [](Payload& p) { p.fixed = {12}; }, "fixed", 8,
       "fixed vertex 12 (entry 0) is out of range [0, 12)"},
  });
}

TEST(ReducedModelFile, RejectsAbsurdSizeFieldsWithoutAllocating) {
  const std::uint64_t huge = std::uint64_t{1} << 40;
  const Payload valid = Payload::of(model(), box());
  Payload many_groups = valid;
  many_groups.group_count = huge;
  struct Case {
    const char* name;
    std::string bytes;
    std::string message;
  };
  const Case cases[] = {
      {"group count", many_groups.bytes(),
       at("group count") + "1099511627776 material groups cannot fit in the "},
      {"cubic count",
       valid.bytes_until("group 0 part 0 cubic", [&](ContainerWriter& w) { w.write_u64(huge); }),
       at("group 0 part 0 cubic") +
           "group 0's λ part cubic coefficients: 1099511627776 items of 8 bytes do not fit in "
           "the 0 bytes that remain"},
      {"K rows",
       valid.bytes_until("group 0 part 0 K",
                         [&](ContainerWriter& w) {
                           w.write_u64(huge);
                           w.write_u64(3);
                         }),
       at("group 0 part 0 K") +
           "group 0's λ part K: 1099511627776×3 exceeds the dimension limit of 2147483647"},
      {"mass entries",
       valid.bytes_until("group 1 mass",
                         [&](ContainerWriter& w) {
                           w.write_u64(3);
                           w.write_u64(2000000000);
                         }),
       at("group 1 mass") +
           "group 1's unit-density mass: 3×2000000000 entries of 8 bytes do not fit in the 0 "
           "bytes that remain"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::filesystem::path file = test::scratch_file("forged.khzmodel");
    write_bytes(file, c.bytes);
    test::largest_allocation = 0;
    EXPECT_TRUE(test::throws_with_message([&] { read_reduced_model(file); },
                                          file.string() + ": " + c.message));
    EXPECT_LT(test::largest_allocation.load(), std::size_t{1} << 20);
  }
}

}  // namespace
}  // namespace khz::reduced
