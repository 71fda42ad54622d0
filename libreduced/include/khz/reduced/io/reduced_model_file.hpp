#pragma once
// Reduced model files (".khzmodel"): a ReducedModel — basis, integrator defaults, and per
// material group the material, the energy polynomial parts and the unit-density reduced mass —
// stored with the fingerprint of the mesh it was computed on, in the checked binary container of
// binary_container.hpp. A haptic program loads one without the mesh.
//
// Format version 1. Container magic "KHZMODEL"; the payload, in order:
//
//   The basis, laid out exactly as the payload of a basis file (basis_file.hpp):
//   u64     mesh fingerprint (mesh_fingerprint() of the mesh the model was computed on)
//   u64     n, the mesh's vertex count
//   u64     r, the model's dimension: 1 ≤ r ≤ reduced_model_file_max_dimension
//   string  recipe (Basis::recipe, UTF-8)
//   ints    fixed vertices: zero-based, sorted, distinct, each in [0, n)
//   matrix  U, 3n × r, column-major; row 3v + c is coordinate c (x, y, z) of vertex v
//
//   The integrator defaults (ReducedIntegratorDefaults):
//   f64     Δt (s), > 0
//   f64     Newmark β̃ ∈ [0, ½]
//   f64     Newmark γ̃ ∈ [0, 1]
//   f64     Rayleigh α (1/s), ≥ 0
//   f64     Rayleigh β (s), ≥ 0
//   i32     j_max, the Newton iteration limit, ≥ 1
//   f64     Newton tolerance (relative residual), > 0
//
//   u64     G, the number of material groups, ≥ 1; then for each group g:
//   u32     material kind: 0 = StVK, 1 = general linear
//           kind 0: f64 λ (Pa), f64 μ (Pa)   (as Material::stvk_lame accepts)
//           kind 1: matrix C₀, 6×6 Voigt (Pa), then f64 s > 0   (s·C₀ as Material::general
//                   accepts)
//   f64     density ρ_g (kg/m³), > 0
//           the energy parts (ReducedMaterialGroup::parts): two for StVK (the λ part, then the
//           μ part), one for general groups (the C₀ part), each an EnergyPolynomial in r
//           coordinates (energy_polynomial.hpp):
//     matrix  K, r × r, symmetric (N·m per unit q²)
//     doubles cubic coefficients, C(r+2, 3) of them, in colexicographic order
//     doubles quartic coefficients, C(r+3, 4) of them, in colexicographic order
//   matrix  UᵀM_gU at unit density, r × r
//
// Every f64 must be finite, and the reduced mass Σ_g ρ_g UᵀM_gU positive definite (as
// ReducedModel::from_parts requires). Everything is little-endian and the whole file is covered
// by an XXH3-64 checksum, so the values read back are bit for bit the values written. Not stored,
// because they are implied: an StVK group's reference elasticity and scale (read back as zero and
// 1), and a general group's material elasticity, which the reader rebuilds as
// Material::general(s·C₀, ρ) exactly as ReducedModel::set_elasticity_scale() does (so it is bit
// for bit the one of a model made by precompute() and the setters).

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/material.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace khz::reduced {

/// The extension reduced model files use (the readers do not insist on it).
inline constexpr std::string_view reduced_model_file_extension = ".khzmodel";

/// The container format of reduced model files; version is the newest this build writes and
/// reads.
inline constexpr ContainerFormat reduced_model_file_format{"KHZMODEL",
                                                           "Kilohertz reduced model file", 1};

/// Largest model dimension r a model file holds (a model with r = 10⁴ would already have
/// 4·10¹⁴ quartic coefficients per part); it keeps the coefficient counts far from overflow.
inline constexpr Eigen::Index reduced_model_file_max_dimension = 10000;

/// One material group as read_reduced_model_info() reports it.
struct ReducedModelGroupInfo {
  /// The group's material: StVK (λ, μ, ρ) or general (elasticity s·C₀, ρ).
  Material material;
  /// s of a general group's elasticity s·C₀ (1 for StVK groups).
  double elasticity_scale = 1.0;
};

/// What a reduced model file holds besides its coefficients (for `khz info`).
struct ReducedModelFileInfo {
  /// The facts a basis file's header holds, for this file: its format version (1 ≤ v ≤
  /// reduced_model_file_format.version), the mesh fingerprint, n, r, the fixed-vertex count, the
  /// recipe and the size of this file on disk.
  BasisFileInfo basis;
  /// The material groups in the file's order.
  std::vector<ReducedModelGroupInfo> groups;
  /// The integrator settings the model was saved with.
  ReducedIntegratorDefaults defaults;
};

/// Writes `model`, computed on `mesh`, to `file` (by convention with
/// reduced_model_file_extension), atomically: a crash or a failure leaves the previous file, if
/// any, untouched. A model is valid by construction; what is checked is that it fits `mesh`.
/// @param mesh  The mesh the model's basis was computed on; only its fingerprint and vertex count
///              are stored.
/// @throws Error "<file>: cannot write reduced model: ..." if U does not have 3·#V rows, a fixed
///         vertex is out of [0, #V) or unsorted, or r exceeds reduced_model_file_max_dimension
///         (nothing is written); IoError naming `file` and the system's reason if writing fails.
KHZ_REDUCED_API void write_reduced_model(const std::filesystem::path& file,
                                         const ReducedModel& model, const VolumeMesh& mesh);

/// Reads a reduced model file written for `mesh` (the set-up path, which has the mesh). The
/// result is bit for bit what write_reduced_model() got (see the note on materials above).
/// @throws IoError if the file cannot be read.
/// @throws ParseError "<file>: byte <offset>: <message>" if it is not a reduced model file, was
///         written by a newer format version, is truncated or corrupted (checksum), or holds an
///         invalid value: a size that disagrees with n or r, a non-finite number, unsorted or
///         out-of-range fixed vertices, an unknown material kind, an invalid material or
///         integrator setting, an asymmetric K, or groups whose reduced mass is not positive
///         definite. The offset is that of the offending value (for a whole-model inconsistency,
///         that of the group count).
/// @throws Error if the model belongs to a different mesh (the fingerprints differ); the message
///         shows both fingerprints and vertex counts.
KHZ_REDUCED_API ReducedModel read_reduced_model(const std::filesystem::path& file,
                                                const VolumeMesh& mesh);

/// Reads a reduced model file without its mesh (the runtime path: a haptic program needs no
/// mesh). Every value is checked as by read_reduced_model(file, mesh); only the mesh
/// fingerprint is not compared. @throws IoError, ParseError as read_reduced_model(file, mesh).
KHZ_REDUCED_API ReducedModel read_reduced_model(const std::filesystem::path& file);

/// read_reduced_model(file) on bytes in memory; `source` names them in messages (for fuzzers,
/// and for models kept somewhere other than a file). @throws ParseError as read_reduced_model().
KHZ_REDUCED_API ReducedModel parse_reduced_model(std::string bytes, std::string source);

/// Reads and checks a whole reduced model file, as read_reduced_model(file) does (so a file this
/// accepts loads), and reports its header facts, materials and integrator defaults.
/// @throws IoError, ParseError as read_reduced_model(file).
KHZ_REDUCED_API ReducedModelFileInfo read_reduced_model_info(const std::filesystem::path& file);

}  // namespace khz::reduced
