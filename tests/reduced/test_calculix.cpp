// Kilohertz checked against CalculiX (ccx 2.20, Debian's calculix-ccx): the same meshes, node for
// node, written to .inp decks that ccx solves, and its results compared with Kilohertz's own —
// the assembled K(0) and M entry by entry (*FREQUENCY, SOLVER=MATRIXSTORAGE), the frequencies of
// clamped beams and of a Mesh_3 tetrahedralization (*FREQUENCY), and a cantilever bent by 30 % of
// its length (*STATIC with NLGEOM: ccx's linear *ELASTIC is then StVK, PK2 = C : Green strain).
// docs/REDUCED_MODELS.md ("Checked against CalculiX") lists the measured figures.
//
// Every number both programs use goes through the deck's text: ccx reads each number from at most
// 20 characters (Fortran f20.0), so coordinates, material constants and loads are written with 14
// significant digits, and Kilohertz is given the values read back from that text.
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/meshing/tetrahedralize.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/static_solver.hpp>
#include <khz/test/external_program.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <numbers>
#include <ostream>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace khz::reduced {
namespace {

// ---------------------------------------------------------------------------------------------
// Running ccx

/// What ccx printed, for a failure message: its *ERROR and *WARNING lines, then its last lines.
std::string ccx_output_excerpt(const std::string& output) {
  std::vector<std::string> lines;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::string excerpt;
  for (const std::string& line : lines) {
    if (line.find("*ERROR") != std::string::npos || line.find("*WARNING") != std::string::npos) {
      excerpt += line + "\n";
    }
  }
  excerpt += "--- last lines of ccx's output ---\n";
  const std::size_t tail = 60;
  for (std::size_t i = lines.size() > tail ? lines.size() - tail : 0; i < lines.size(); ++i) {
    excerpt += lines[i] + "\n";
  }
  return excerpt;
}

/// Runs `ccx -i <job>` on one thread in the job's directory (ccx writes files there, e.g.
/// spooles.out). Throws, quoting its output, unless ccx exits with 0, prints no *ERROR or
/// *WARNING (it exits with 0 after some errors, e.g. ARPACK's) and wrote each of `outputs` (file
/// extensions). KHZ_CCX_PATH comes from find_program() in tests/CMakeLists.txt (empty when not
/// found: the test fails, naming the package).
void run_ccx(const std::filesystem::path& job, std::initializer_list<const char*> outputs) {
  const std::string program =
      test::required_program(KHZ_CCX_PATH, "CalculiX (ccx)", "calculix-ccx");
  test::ProgramOptions options;
  options.working_directory = job.parent_path();
  options.environment = {"CCX_NPROC_STIFFNESS=1", "CCX_NPROC_EQUATION_SOLVER=1",
                         "CCX_NPROC_RESULTS=1", "NUMBER_OF_CPUS=1"};
  const test::ProgramRun run = test::run_program(program, {"-i", job.filename().string()}, options);
  const std::string& output = run.output;
  std::string problem;
  if (run.exit_code != 0) {
    problem = run.exit_code < 0 ? "was killed by a signal"
                                : "exited with status " + std::to_string(run.exit_code);
  } else if (output.find("*ERROR") != std::string::npos ||
             output.find("*WARNING") != std::string::npos) {
    problem = "reported an error or warning";
  } else {
    for (const char* extension : outputs) {
      if (!std::filesystem::exists(job.string() + extension)) {
        problem = std::string("wrote no ") + extension + " file";
      }
    }
  }
  if (!problem.empty()) {
    throw std::runtime_error("ccx -i " + job.string() + " " + problem + ":\n" +
                             ccx_output_excerpt(output));
  }
}

/// A fresh job (a path without extension) in a directory of its own, which ccx works in, in the
/// running test's scratch space.
std::filesystem::path new_job(std::string_view name) {
  const std::filesystem::path directory = test::scratch_directory(name);
  std::filesystem::create_directories(directory);
  return directory / name;
}

std::filesystem::path with_extension(const std::filesystem::path& job, const char* extension) {
  return job.string() + extension;
}

// ---------------------------------------------------------------------------------------------
// Writing the deck

/// A number as the deck holds it: 14 significant digits in at most 20 characters.
std::string deck_number(double value) {
  std::array<char, 32> text{};
  std::snprintf(text.data(), text.size(), "%.13e", value);
  return text.data();
}

/// The value ccx reads from deck_number(value) (gfortran converts with strtod, correctly rounded).
double as_read(double value) { return std::strtod(deck_number(value).c_str(), nullptr); }

/// The mesh with every coordinate as ccx reads it from the deck.
VolumeMesh as_read(VolumeMesh mesh) {
  mesh.vertices = mesh.vertices.unaryExpr([](double x) { return as_read(x); });
  return mesh;
}

/// An isotropic material as the deck states it.
struct Elastic {
  double young;    ///< Pa
  double poisson;  ///< –
  double density;  ///< kg/m³

  Material material() const {
    return Material::stvk(as_read(young), as_read(poisson), as_read(density));
  }
};

// Rubber-like; ν ≠ 0 so that both Lamé parameters enter every comparison.
constexpr Elastic rubber{1e6, 0.3, 1100.0};

/// A deck for `ccx -i`: the mesh (vertex v is node v + 1, element e is element e + 1: C3D4, or
/// C3D8 — fully integrated, 2×2×2 Gauss points, as Kilohertz; the node orders agree), the
/// material, the `clamped` vertices held in x, y and z, and `step`.
void write_deck(const std::filesystem::path& job, const VolumeMesh& mesh, const Elastic& material,
                std::span<const int> clamped, const std::string& step) {
  std::ofstream deck(with_extension(job, ".inp"));
  deck << "** Written by test_reduced_calculix (Kilohertz)\n*NODE, NSET=NALL\n";
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    deck << v + 1;
    for (int axis = 0; axis < 3; ++axis) deck << ", " << deck_number(mesh.vertices(v, axis));
    deck << "\n";
  }
  const bool tetrahedra = mesh.element_type == ElementType::tetrahedron;
  deck << "*ELEMENT, TYPE=" << (tetrahedra ? "C3D4" : "C3D8") << ", ELSET=EALL\n";
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    deck << e + 1;
    for (const int node : mesh.elements.row(e)) deck << ", " << node + 1;
    deck << "\n";
  }
  deck << "*MATERIAL, NAME=KHZ\n*ELASTIC\n"
       << deck_number(material.young) << ", " << deck_number(material.poisson) << "\n*DENSITY\n"
       << deck_number(material.density) << "\n*SOLID SECTION, ELSET=EALL, MATERIAL=KHZ\n";
  if (!clamped.empty()) {
    deck << "*NSET, NSET=CLAMPED\n";
    for (const int v : clamped) deck << v + 1 << ",\n";
    deck << "*BOUNDARY\nCLAMPED, 1, 3\n";
  }
  deck << step;
  if (!deck.flush()) throw IoError(with_extension(job, ".inp").string() + ": cannot write");
}

/// K(0) and M written to <job>.sti and <job>.mas, their rows' dofs to <job>.dof; nothing solved.
const std::string matrix_step = "*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n*END STEP\n";

/// The lowest `count` eigenfrequencies, printed to <job>.dat.
std::string frequency_step(int count) {
  return "*STEP\n*FREQUENCY\n" + std::to_string(count) + "\n*END STEP\n";
}

/// Static equilibrium with geometric nonlinearity under the nodal forces `f` (N, 3n, as ccx reads
/// them): a step in increments of a tenth of the load, then a second step at the same load that
/// only iterates. ccx's residual criteria are tightened from 0.5 % of the mean force to 1e-13, yet
/// it ends an increment after a correction of ~1e-6 m, leaving errors of ~3e-10 m; the second
/// step always iterates twice and brings them to round-off (last correction ~1e-16 m).
/// Displacements and element energies are printed to <job>.dat after every increment.
std::string nonlinear_static_step(const Eigen::VectorXd& f) {
  std::string step =
      "*STEP, NLGEOM, INC=1000\n*CONTROLS, PARAMETERS=FIELD\n1e-13, 1e-13, , , 1e-13\n"
      "*STATIC\n0.1, 1.0, 1e-5, 0.1\n*CLOAD\n";
  for (Eigen::Index d = 0; d < f.size(); ++d) {
    if (f(d) == 0.0) continue;
    step += std::to_string(d / 3 + 1) + ", " + std::to_string(d % 3 + 1) + ", " +
            deck_number(f(d)) + "\n";
  }
  const std::string prints = "*NODE PRINT, NSET=NALL\nU\n*EL PRINT, ELSET=EALL\nELSE\n";
  return step + prints + "*END STEP\n*STEP, NLGEOM\n*STATIC\n1.0, 1.0, 1e-5, 1.0\n" + prints +
         "*END STEP\n";
}

// ---------------------------------------------------------------------------------------------
// Reading ccx's outputs

std::vector<std::string> read_lines(const std::filesystem::path& file) {
  std::vector<std::string> lines;
  std::istringstream in(test::read_bytes(file));
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string_view> split(std::string_view line, std::string_view separators = " \t") {
  std::vector<std::string_view> tokens;
  for (std::size_t start = line.find_first_not_of(separators); start != std::string_view::npos;) {
    const std::size_t end = std::min(line.find_first_of(separators, start), line.size());
    tokens.push_back(line.substr(start, end - start));
    start = line.find_first_not_of(separators, end);
  }
  return tokens;
}

template <typename Number>
bool parse_whole(std::string_view text, Number& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

/// The Kilohertz dof (3v + axis) of each row of ccx's matrices: <job>.dof holds "node.direction"
/// per row. Every dof must appear once (decks for matrices hold no boundary conditions).
std::vector<int> read_dofs(const std::filesystem::path& file, Eigen::Index num_dofs) {
  const std::vector<std::string> lines = read_lines(file);
  std::vector<int> dofs;
  std::vector<bool> seen(num_dofs, false);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::vector<std::string_view> parts = split(lines[i], " \t.");
    int node = 0, direction = 0;
    if (parts.size() != 2 || !parse_whole(parts[0], node) || !parse_whole(parts[1], direction) ||
        node < 1 || node > num_dofs / 3 || direction < 1 || direction > 3) {
      throw ParseError::at_line(file.string(), i + 1, "expected node.direction of the mesh");
    }
    const int dof = 3 * (node - 1) + direction - 1;
    if (seen[dof]) throw ParseError::at_line(file.string(), i + 1, "dof listed twice");
    seen[dof] = true;
    dofs.push_back(dof);
  }
  if (static_cast<Eigen::Index>(dofs.size()) != num_dofs) {
    throw ParseError::at_line(
        file.string(), lines.size(),
        "lists " + std::to_string(dofs.size()) + " dofs, the mesh has " + std::to_string(num_dofs));
  }
  return dofs;
}

/// A symmetric matrix from ccx's "row column value" lines (1-based rows of the .dof file, one
/// triangle; values printed with 14 significant digits), in Kilohertz's dof numbering.
Eigen::MatrixXd read_matrix(const std::filesystem::path& file, const std::vector<int>& dofs) {
  const Eigen::Index n = static_cast<Eigen::Index>(dofs.size());
  Eigen::MatrixXd matrix = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXi count = Eigen::MatrixXi::Zero(n, n);
  const std::vector<std::string> lines = read_lines(file);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::vector<std::string_view> parts = split(lines[i]);
    int row = 0, column = 0;
    double value = 0.0;
    if (parts.size() != 3 || !parse_whole(parts[0], row) || !parse_whole(parts[1], column) ||
        !parse_whole(parts[2], value) || row < 1 || row > n || column < 1 || column > n) {
      throw ParseError::at_line(file.string(), i + 1,
                                "expected row, column (1.." + std::to_string(n) + ") and value");
    }
    const int a = dofs[row - 1], b = dofs[column - 1];
    if (++count(a, b) > 1 || (a != b && ++count(b, a) > 1)) {
      throw ParseError::at_line(file.string(), i + 1, "entry given twice");
    }
    matrix(a, b) = matrix(b, a) = value;
  }
  return matrix;
}

/// A number as ccx prints it, and half a unit of its last printed digit: the print resolution.
struct Printed {
  double value = 0.0;
  double resolution = 0.0;
};

/// Parses "-1.234567E-03" or "0.1234567E+02"; false if `token` is not such a number.
bool parse_printed(std::string_view token, Printed& printed) {
  const std::size_t point = token.find('.'), exponent_mark = token.find_first_of("Ee");
  int exponent = 0;
  if (point == std::string_view::npos || exponent_mark == std::string_view::npos ||
      exponent_mark < point || !parse_whole(token, printed.value)) {
    return false;
  }
  std::string_view exponent_text = token.substr(exponent_mark + 1);
  if (!exponent_text.empty() && exponent_text.front() == '+') exponent_text.remove_prefix(1);
  if (!parse_whole(exponent_text, exponent)) return false;
  const int digits = static_cast<int>(exponent_mark - point - 1);
  printed.resolution = 0.5 * std::pow(10.0, exponent - digits);
  return true;
}

/// One row of a .dat table: a node, element or mode number and its printed values.
struct DatRow {
  int id = 0;
  std::vector<Printed> values;
};

/// A table of a .dat file: the heading line and the rows under it.
struct DatTable {
  std::string heading;
  std::vector<DatRow> rows;
};

/// The last table in a .dat file whose heading contains `heading`: its rows are the lines of an
/// integer and `columns` numbers from the first such line after the heading to the next blank one.
DatTable read_dat_table(const std::filesystem::path& dat, std::string_view heading, int columns) {
  const std::vector<std::string> lines = read_lines(dat);
  std::size_t at = lines.size();
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].find(heading) != std::string::npos) at = i;
  }
  if (at == lines.size()) {
    throw ParseError::at_line(dat.string(), lines.size(),
                              "no table headed \"" + std::string(heading) + "\"");
  }
  DatTable table{lines[at], {}};
  const auto parse_row = [&](std::string_view line, DatRow& row) {
    const std::vector<std::string_view> parts = split(line);
    if (static_cast<int>(parts.size()) != columns + 1 || !parse_whole(parts[0], row.id)) {
      return false;
    }
    row.values.resize(columns);
    for (int c = 0; c < columns; ++c) {
      if (!parse_printed(parts[c + 1], row.values[c])) return false;
    }
    return true;
  };
  std::size_t i = at + 1;
  DatRow row;
  while (i < lines.size() && !parse_row(lines[i], row)) ++i;
  for (; i < lines.size() && !split(lines[i]).empty(); ++i) {
    if (!parse_row(lines[i], row)) {
      throw ParseError::at_line(dat.string(), i + 1,
                                "expected a number and " + std::to_string(columns) + " values");
    }
    table.rows.push_back(row);
  }
  if (table.rows.empty()) throw ParseError::at_line(dat.string(), at + 1, "table has no rows");
  return table;
}

/// Eigenfrequencies (Hz, "CYCLES/TIME") of a *FREQUENCY step's .dat file, lowest first.
std::vector<Printed> read_frequencies(const std::filesystem::path& dat) {
  const DatTable table = read_dat_table(dat, "E I G E N V A L U E   O U T P U T", 4);
  std::vector<Printed> frequencies;
  for (const DatRow& row : table.rows) frequencies.push_back(row.values[2]);
  return frequencies;
}

// ---------------------------------------------------------------------------------------------
// Kilohertz's side

Eigen::MatrixXd stiffness_at_rest(const FemModel& model) {
  SparseMatrix k = model.stiffness_pattern();
  model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), k);
  return Eigen::MatrixXd(k);
}

/// ccx's C3D4 mass matrix: ρ φ_a φ_b integrated at the centroid alone, where every φ is ¼ —
/// ρV/16 for every node pair of an element (Kilohertz integrates exactly: ρV/20 (1 + δ_ab)).
SparseMatrix one_point_tet_mass(const FemModel& model) {
  const VolumeMesh& mesh = model.mesh();
  std::vector<Eigen::Triplet<double, int>> triplets;
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    const double pair_mass =
        model.element_material(e).density() * model.quadrature_weight(e, 0) / 16.0;
    for (const int a : mesh.elements.row(e)) {
      for (const int b : mesh.elements.row(e)) {
        for (int i = 0; i < 3; ++i) triplets.emplace_back(3 * a + i, 3 * b + i, pair_mass);
      }
    }
  }
  SparseMatrix mass(model.num_dofs(), model.num_dofs());
  mass.setFromTriplets(triplets.begin(), triplets.end());
  return mass;
}

/// The lowest `count` frequencies (Hz) of K(0) ψ = λ M ψ on the free dofs for any mass matrix M,
/// by subspace iteration (X ← K⁻¹ M X on 2·count vectors, Rayleigh–Ritz after each step) until
/// the eigenvalues change by less than 1e-10 relatively: converged far below ccx's print
/// resolution (5e-7), above the round-off jitter of the Ritz values (~3e-12 on the dino).
Eigen::VectorXd lowest_frequencies(const FemModel& model, const SparseMatrix& mass,
                                   std::span<const int> clamped, int count) {
  const FixedDofs fixed(model.mesh().num_vertices(), clamped);
  SparseMatrix k = model.stiffness_pattern();
  model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), k);
  const SparseMatrix k_free = fixed.restrict_matrix(k), m_free = fixed.restrict_matrix(mass);
  const Eigen::SimplicialLLT<SparseMatrix> k_factor(k_free);
  if (k_factor.info() != Eigen::Success) throw std::runtime_error("K(0) is not positive definite");
  Eigen::MatrixXd x = Eigen::MatrixXd::Random(k_free.rows(), 2 * count);
  Eigen::VectorXd previous = Eigen::VectorXd::Zero(count);
  for (int iteration = 0; iteration < 200; ++iteration) {
    const Eigen::MatrixXd y = k_factor.solve(m_free * x);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(
        y.transpose() * (k_free * y), y.transpose() * (m_free * y));
    if (ritz.info() != Eigen::Success) throw std::runtime_error("Rayleigh-Ritz step failed");
    x = y * ritz.eigenvectors();
    const Eigen::VectorXd values = ritz.eigenvalues().head(count);
    if (((values - previous).array().abs() <= 1e-10 * values.array()).all()) {
      return values.cwiseSqrt() / (2.0 * std::numbers::pi);
    }
    previous = values;
  }
  throw std::runtime_error("subspace iteration did not converge");
}

/// max |a − b| / max |b|.
double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

std::vector<int> vertices_at_x(const VolumeMesh& mesh, double x) {
  const Eigen::AlignedBox3d plane(Eigen::Vector3d(x - 1e-9, -1e9, -1e9),
                                  Eigen::Vector3d(x + 1e-9, 1e9, 1e9));
  return vertices_in_box(mesh.vertices, plane);
}

// ---------------------------------------------------------------------------------------------
// Tolerances

// Matrix entries: the files print 14 significant digits (up to 5e-14 of an entry), and an entry
// sums up to a few dozen element contributions, whose round-off in either program stays below
// ~5e-14 of the largest entry (measured in all: 5.5e-15 for hexahedra, 2.3e-14 for tetrahedra).
constexpr double matrix_tolerance = 1e-13;

/// |computed − printed| in units of the print resolution plus `slack`: at most 1 for a match.
double print_error(double computed, const Printed& printed, double slack) {
  return std::abs(computed - printed.value) / (printed.resolution + slack);
}

/// Whether `computed` matches ccx's `printed` value to its print resolution, allowing `slack` for
/// what the two computations may differ in beyond rounding.
::testing::AssertionResult matches_print(double computed, const Printed& printed, double slack) {
  const double difference = std::abs(computed - printed.value);
  if (difference <= printed.resolution + slack) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "Kilohertz " << computed << ", ccx prints " << printed.value << ": difference "
         << difference << " exceeds the print resolution " << printed.resolution << " + " << slack;
}

// ---------------------------------------------------------------------------------------------
// 1. Stiffness and mass matrices, entry by entry

// A 0.3 × 0.05 × 0.04 m bar of 6 × 2 × 2 cells: 63 nodes, 189 dofs, unconstrained.
VolumeMesh small_bar(ElementType type) {
  const Eigen::Vector3d min_corner(0, 0, 0), max_corner(0.3, 0.05, 0.04);
  const Eigen::Vector3i cells(6, 2, 2);
  return as_read(type == ElementType::tetrahedron ? box_tet_mesh(min_corner, max_corner, cells)
                                                  : box_hex_mesh(min_corner, max_corner, cells));
}

struct CcxMatrices {
  Eigen::MatrixXd stiffness, mass;
};

CcxMatrices ccx_matrices(const FemModel& model, std::string_view name) {
  const std::filesystem::path job = new_job(name);
  write_deck(job, model.mesh(), rubber, {}, matrix_step);
  run_ccx(job, {".sti", ".mas", ".dof"});
  const std::vector<int> dofs = read_dofs(with_extension(job, ".dof"), model.num_dofs());
  return {read_matrix(with_extension(job, ".sti"), dofs),
          read_matrix(with_extension(job, ".mas"), dofs)};
}

TEST(CalculiX, HexahedronStiffnessAndMassMatchEntryByEntry) {
  const FemModel model(small_bar(ElementType::hexahedron), {rubber.material()});
  const CcxMatrices ccx = ccx_matrices(model, "hexahedra");
  const double k_difference = relative_difference(stiffness_at_rest(model), ccx.stiffness);
  const double m_difference = relative_difference(Eigen::MatrixXd(model.mass_matrix()), ccx.mass);
  std::printf("C3D8: max |K - K_ccx| / max |K_ccx| = %.2e, max |M - M_ccx| / max |M_ccx| = %.2e\n",
              k_difference, m_difference);
  EXPECT_LE(k_difference, matrix_tolerance);
  EXPECT_LE(m_difference, matrix_tolerance);
}

TEST(CalculiX, TetrahedronStiffnessMatchesAndItsMassIsTheOnePointRule) {
  const FemModel model(small_bar(ElementType::tetrahedron), {rubber.material()});
  const CcxMatrices ccx = ccx_matrices(model, "tetrahedra");
  const double k_difference = relative_difference(stiffness_at_rest(model), ccx.stiffness);
  const Eigen::MatrixXd exact_mass(model.mass_matrix());
  const double one_point_difference =
      relative_difference(Eigen::MatrixXd(one_point_tet_mass(model)), ccx.mass);
  // Both rules integrate constants exactly: the same mass at every node (ρV/4 per element).
  const double row_sum_difference =
      relative_difference(exact_mass.rowwise().sum(), ccx.mass.rowwise().sum());
  const double exact_difference = relative_difference(exact_mass, ccx.mass);
  std::printf(
      "C3D4: max |K - K_ccx| / max |K_ccx| = %.2e; M_ccx against the one-point rule %.2e, "
      "against Kilohertz's exact mass %.2e (row sums %.2e)\n",
      k_difference, one_point_difference, exact_difference, row_sum_difference);
  EXPECT_LE(k_difference, matrix_tolerance);
  EXPECT_LE(one_point_difference, matrix_tolerance);
  EXPECT_LE(row_sum_difference, matrix_tolerance);
  // The rules differ by ρV/20 − ρV/16 on the diagonal and ρV/16 − ρV/20 off it: O(1) relatively.
  EXPECT_GT(exact_difference, 0.1);
}

// ---------------------------------------------------------------------------------------------
// 2. Eigenfrequencies of clamped beams

// A 0.4 × 0.05 × 0.04 m beam clamped at x = 0; unequal sides keep its frequencies simple.
VolumeMesh beam(ElementType type, const Eigen::Vector3i& cells) {
  const Eigen::Vector3d min_corner(0, 0, 0), max_corner(0.4, 0.05, 0.04);
  return as_read(type == ElementType::tetrahedron ? box_tet_mesh(min_corner, max_corner, cells)
                                                  : box_hex_mesh(min_corner, max_corner, cells));
}

constexpr int frequency_count = 8;

std::vector<Printed> ccx_frequencies(const FemModel& model, std::span<const int> clamped,
                                     std::string_view name) {
  const std::filesystem::path job = new_job(name);
  write_deck(job, model.mesh(), rubber, clamped, frequency_step(frequency_count));
  run_ccx(job, {".dat"});
  std::vector<Printed> frequencies = read_frequencies(with_extension(job, ".dat"));
  if (frequencies.size() != static_cast<std::size_t>(frequency_count)) {
    throw std::runtime_error(std::string(name) + ": ccx printed " +
                             std::to_string(frequencies.size()) + " frequencies, not " +
                             std::to_string(frequency_count));
  }
  return frequencies;
}

// Frequencies: ccx prints 7 significant digits. Kilohertz's ARPACK converges to ~1e-12 relative,
// lowest_frequencies() to 1e-10; ccx's ARPACK (Ritz residual tolerance 1e-2) lands within the
// print resolution too (measured: at most 0.91 of it).
constexpr double frequency_slack = 1e-10;

/// How far computed frequencies (Hz) are from ccx's: relatively, and in print resolutions.
struct FrequencyDifference {
  double relative = 0.0;
  double in_resolutions = 0.0;
};

FrequencyDifference expect_frequencies_match(const Eigen::VectorXd& computed,
                                             const std::vector<Printed>& printed) {
  FrequencyDifference largest;
  for (int i = 0; i < frequency_count; ++i) {
    const double slack = frequency_slack * printed[i].value;
    EXPECT_TRUE(matches_print(computed[i], printed[i], slack)) << "mode " << i + 1;
    largest.relative =
        std::max(largest.relative, std::abs(computed[i] - printed[i].value) / printed[i].value);
    largest.in_resolutions =
        std::max(largest.in_resolutions, print_error(computed[i], printed[i], slack));
  }
  return largest;
}

TEST(CalculiX, HexahedronBeamFrequenciesMatch) {
  const FemModel model(beam(ElementType::hexahedron, {16, 2, 2}), {rubber.material()});
  const std::vector<int> clamped = vertices_at_x(model.mesh(), 0.0);
  LinearModesOptions options;
  options.num_modes = frequency_count;
  const Eigen::VectorXd computed = compute_linear_modes(model, clamped, options).frequencies_hz();
  const std::vector<Printed> printed = ccx_frequencies(model, clamped, "hexahedron_beam");
  const FrequencyDifference largest = expect_frequencies_match(computed, printed);
  std::printf(
      "C3D8 beam: %d frequencies %.4f-%.4f Hz, largest relative difference %.2e (%.2f print "
      "resolutions)\n",
      frequency_count, computed[0], computed[frequency_count - 1], largest.relative,
      largest.in_resolutions);
}

TEST(CalculiX, TetrahedronBeamFrequenciesMatchWithTheOnePointMass) {
  const FemModel model(beam(ElementType::tetrahedron, {16, 2, 2}), {rubber.material()});
  const std::vector<int> clamped = vertices_at_x(model.mesh(), 0.0);
  const Eigen::VectorXd one_point =
      lowest_frequencies(model, one_point_tet_mass(model), clamped, frequency_count);
  const std::vector<Printed> printed = ccx_frequencies(model, clamped, "tetrahedron_beam");
  const FrequencyDifference largest = expect_frequencies_match(one_point, printed);

  // Kilohertz's own modes (exact consistent mass) against ccx's: the mass rule alone differs.
  LinearModesOptions options;
  options.num_modes = frequency_count;
  const Eigen::VectorXd exact = compute_linear_modes(model, clamped, options).frequencies_hz();
  double smallest_shift = 1.0, largest_shift = 0.0;
  for (int i = 0; i < frequency_count; ++i) {
    const double shift = printed[i].value / exact[i] - 1.0;
    smallest_shift = std::min(smallest_shift, shift);
    largest_shift = std::max(largest_shift, shift);
  }
  std::printf(
      "C3D4 beam: %d frequencies %.4f-%.4f Hz, largest relative difference %.2e (%.2f print "
      "resolutions) with the one-point mass; ccx / exact-mass frequencies - 1 in [%.4f, %.4f]\n",
      frequency_count, one_point[0], one_point[frequency_count - 1], largest.relative,
      largest.in_resolutions, smallest_shift, largest_shift);
  // Per element the exact mass exceeds the one-point mass by ρV/20 (I − ¼ 11ᵀ), positive
  // semidefinite: no frequency can fall (Courant–Fischer). Measured: +0.02 % to +7.0 %.
  EXPECT_GE(smallest_shift, 0.0);
  EXPECT_GT(largest_shift, 0.01);
  EXPECT_LT(largest_shift, 0.1);
}

// ---------------------------------------------------------------------------------------------
// 3. A geometrically nonlinear cantilever

struct TipLoadCase {
  ElementType type;
  double load;  ///< N along z, split over the tip nodes: bends the tip by ~30 % of the length.
};

void PrintTo(const TipLoadCase& tip_load, std::ostream* out) {
  *out << (tip_load.type == ElementType::tetrahedron ? "tetrahedra, " : "hexahedra, ")
       << tip_load.load << " N";
}

class CalculiXTipLoad : public ::testing::TestWithParam<TipLoadCase> {};

TEST_P(CalculiXTipLoad, NonlinearStaticSolutionMatches) {
  const FemModel model(beam(GetParam().type, {10, 2, 2}), {rubber.material()});
  const std::vector<int> clamped = vertices_at_x(model.mesh(), 0.0);
  const std::vector<int> tip = vertices_at_x(model.mesh(), 0.4);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
  for (const int v : tip) f(3 * v + 2) = as_read(GetParam().load / static_cast<double>(tip.size()));

  StaticSolveOptions options;
  options.load_steps = 10;
  options.tolerance = 1e-11;  // of ‖f‖; round-off stalls Newton near 1e-12 here
  const Eigen::VectorXd u = solve_static(model, clamped, f, options).displacement;

  const std::filesystem::path job = new_job("tip_load");
  write_deck(job, model.mesh(), rubber, clamped, nonlinear_static_step(f));
  run_ccx(job, {".dat"});
  const DatTable displacements =
      read_dat_table(with_extension(job, ".dat"), "displacements (vx,vy,vz) for set NALL", 3);
  const DatTable energies =
      read_dat_table(with_extension(job, ".dat"), "internal energy (element, energy)", 1);
  Printed time;
  ASSERT_TRUE(parse_printed(split(displacements.heading).back(), time) && time.value == 2.0)
      << "the last displacements are not those of the second step: " << displacements.heading;
  ASSERT_EQ(static_cast<Eigen::Index>(displacements.rows.size()), model.mesh().num_vertices());
  ASSERT_EQ(static_cast<Eigen::Index>(energies.rows.size()), model.mesh().num_elements());

  // Displacements: both solutions are converged to round-off (measured: no component differs by
  // more than its print resolution + 1e-16 m); the slack covers round-off, e.g. on the mid-plane.
  const double slack = 1e-12 * u.cwiseAbs().maxCoeff();
  std::vector<bool> seen(model.mesh().num_vertices(), false);
  double worst = 0.0, largest = 0.0;
  Eigen::Index worst_dof = 0;
  Printed worst_printed;
  for (const DatRow& row : displacements.rows) {
    ASSERT_TRUE(row.id >= 1 && row.id <= model.mesh().num_vertices() && !seen[row.id - 1])
        << "node " << row.id << " unknown or printed twice";
    seen[row.id - 1] = true;
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Index dof = 3 * (row.id - 1) + axis;
      const double error = print_error(u(dof), row.values[axis], slack);
      if (error > worst) {
        worst = error;
        worst_dof = dof;
        worst_printed = row.values[axis];
      }
      largest = std::max(largest, std::abs(u(dof) - row.values[axis].value));
    }
  }
  EXPECT_TRUE(matches_print(u(worst_dof), worst_printed, slack))
      << "node " << worst_dof / 3 + 1 << " axis " << worst_dof % 3 << ", the worst component";
  // Strain energy: the sum of the elements' printed energies, each within its print resolution.
  Printed energy;
  for (const DatRow& row : energies.rows) {
    energy.value += row.values[0].value;
    energy.resolution += row.values[0].resolution;
  }
  const double computed_energy = model.strain_energy(u);
  EXPECT_TRUE(matches_print(computed_energy, energy, 1e-10 * energy.value));

  // The load is well inside the nonlinear range: the linear solution differs by far more.
  const FixedDofs fixed(model.mesh().num_vertices(), clamped);
  SparseMatrix k = model.stiffness_pattern();
  model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), k);
  const Eigen::SimplicialLDLT<SparseMatrix> linear(fixed.restrict_matrix(k));
  Eigen::VectorXd u_linear;
  fixed.expand_vector(linear.solve(fixed.restrict_vector(f)), u_linear);
  const double nonlinearity = (u - u_linear).cwiseAbs().maxCoeff() / u.cwiseAbs().maxCoeff();
  const double deflection = u(3 * tip[0] + 2);
  std::printf(
      "%s tip load: deflection %.4f m (%.1f %% of the length), max |u - u_linear| / max |u| "
      "%.3f, largest |u - u_ccx| %.2e m (%.2f print resolutions at worst), energy %.6e J, ccx "
      "%.6e J (relative difference %.2e)\n",
      GetParam().type == ElementType::tetrahedron ? "C3D4" : "C3D8", deflection,
      100.0 * deflection / 0.4, nonlinearity, largest, worst, computed_energy, energy.value,
      std::abs(computed_energy - energy.value) / energy.value);
  EXPECT_GT(deflection, 0.25 * 0.4);
  EXPECT_LT(deflection, 0.35 * 0.4);
  EXPECT_GT(nonlinearity, 0.05);
}

std::string tip_load_case_name(const ::testing::TestParamInfo<TipLoadCase>& test) {
  return test.param.type == ElementType::tetrahedron ? "Tetrahedra" : "Hexahedra";
}

INSTANTIATE_TEST_SUITE_P(CalculiX, CalculiXTipLoad,
                         ::testing::Values(TipLoadCase{ElementType::tetrahedron, 4.6},
                                           TipLoadCase{ElementType::hexahedron, 2.4}),
                         tip_load_case_name);

// ---------------------------------------------------------------------------------------------
// 4. A Mesh_3 tetrahedralization of CGAL's dino

TEST(CalculiX, TetrahedralizedDinoFrequenciesMatchWithTheOnePointMass) {
  const TriangleMesh surface = read_triangle_mesh(test::cgal_mesh("dino.off"));
  const Eigen::AlignedBox3d bounds = analyze_mesh(surface).bounding_box;
  // About 2,000 tetrahedra. Much coarser criteria (650 tetrahedra at d/10, d/100) leave a
  // mechanism: a first frequency that is zero to round-off in both programs, so only noise.
  TetrahedralizeOptions options;
  options.facet_size = bounds.diagonal().norm() / 20;
  options.facet_distance = bounds.diagonal().norm() / 200;
  const FemModel model(as_read(tetrahedralize(surface, options)), {rubber.material()});
  // The feet, as in speed_against_error: vertices below y = −0.45 (y is up).
  Eigen::AlignedBox3d feet = bounds;
  feet.max().y() = -0.45;
  const std::vector<int> anchors = vertices_in_box(model.mesh().vertices, feet);

  const Eigen::VectorXd one_point =
      lowest_frequencies(model, one_point_tet_mass(model), anchors, frequency_count);
  const std::vector<Printed> printed = ccx_frequencies(model, anchors, "dino");
  const FrequencyDifference largest = expect_frequencies_match(one_point, printed);
  std::printf(
      "dino: %td tetrahedra, %zu anchors, %d frequencies %.4f-%.4f Hz, largest relative "
      "difference %.2e (%.2f print resolutions) with the one-point mass\n",
      model.mesh().num_elements(), anchors.size(), frequency_count, one_point[0],
      one_point[frequency_count - 1], largest.relative, largest.in_resolutions);
  EXPECT_GT(one_point[0], 1e-3 * one_point[frequency_count - 1]) << "a mechanism";
}

}  // namespace
}  // namespace khz::reduced
