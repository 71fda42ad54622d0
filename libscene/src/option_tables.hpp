#pragma once
// Which option structs a scene file sets through an option table (option_table.hpp), and the
// reading and content-key writing that follow from a struct's table.

#include "option_table.hpp"

#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/pointshell/repulsion_pointshell.hpp>
#include <khz/contact/query/contact_options.hpp>
#include <khz/haptic/coupling/coupling_options.hpp>
#include <khz/haptic/device/device.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/haptic/device/trajectory_device.hpp>
#include <khz/haptic/loop/haptic_loop.hpp>
#include <khz/haptic/world/dynamics_options.hpp>
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/basis/simulation_data_basis.hpp>
#include <khz/reduced/basis/sketch_basis.hpp>
#include <khz/reduced/meshing/tetrahedralize.hpp>
#include <khz/reduced/meshing/voxelize.hpp>
#include <khz/reduced/solvers/static_solver.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/scene/basis_description.hpp>
#include <khz/scene/model_description.hpp>

namespace khz::scene::detail {

// libcontact (contact_option_tables.cpp)
template <>
const OptionTable<contact::DistanceFieldOptions>& option_table();
template <>
const OptionTable<contact::DeformedFieldOptions>& option_table();
template <>
const OptionTable<contact::RepulsionOptions>& option_table();
template <>
const OptionTable<contact::LevelSchedule>& option_table();
template <>
const OptionTable<contact::NestedLevelOptions>& option_table();
template <>
const OptionTable<contact::ContactOptions>& option_table();
template <>
const OptionTable<contact::DegradationOptions>& option_table();
template <>
const OptionTable<contact::CoherenceOptions>& option_table();
template <>
const OptionTable<contact::FrictionOptions>& option_table();

// libhaptic (haptic_option_tables.cpp)
template <>
const OptionTable<haptic::CouplingOptions>& option_table();
template <>
const OptionTable<haptic::LoopOptions>& option_table();
template <>
const OptionTable<haptic::DynamicsOptions>& option_table();
template <>
const OptionTable<haptic::DeviceCapabilities>& option_table();
template <>
const OptionTable<haptic::WorkspaceMapping>& option_table();
template <>
const OptionTable<haptic::SafetyOptions>& option_table();
template <>
const OptionTable<haptic::DeviceDynamics>& option_table();
template <>
const OptionTable<haptic::HandModel>& option_table();
template <>
const OptionTable<haptic::SimulatedOperatorOptions>& option_table();
template <>
const OptionTable<haptic::TrajectoryDeviceOptions>& option_table();

// libreduced, and the scene's own structs that map onto it (reduced_option_tables.cpp)
template <>
const OptionTable<reduced::VoxelizeOptions>& option_table();
template <>
const OptionTable<reduced::TetrahedralizeOptions>& option_table();
template <>
const OptionTable<reduced::ReducedNewmarkOptions>& option_table();
template <>
const OptionTable<reduced::StaticSolveOptions>& option_table();
template <>
const OptionTable<reduced::LinearModesOptions>& option_table();
template <>
const OptionTable<reduced::ModalDerivativeBasisOptions>& option_table();
template <>
const OptionTable<reduced::SketchBasisOptions>& option_table();
template <>
const OptionTable<reduced::SimulationDataBasisOptions>& option_table();
template <>
const OptionTable<MaterialDescription>& option_table();
template <>
const OptionTable<SimulationRunDescription>& option_table();

/// Sets `options` from the keys `block` has, through its struct's table.
/// @throws SceneError at the first value refused.
template <typename Options>
void read_options(const ObjectReader& block, Options& options) {
  option_table<Options>().read(block, options);
}

/// Sets `options` from the block `key` of `parent` through its struct's table, the table's keys
/// being the block's; a block left out keeps `options`. `hints` name keys of other blocks.
/// @throws SceneError at the first problem.
template <typename Options>
void read_block(const ObjectReader& parent, std::string_view key, Options& options,
                std::initializer_list<ObjectReader::Hint> hints = {}) {
  const OptionTable<Options>& table = option_table<Options>();
  if (const auto block = parent.object(key, table.keys(), hints)) table.read(*block, options);
}

/// `options` as content keys write them, through its struct's table.
template <typename Options>
Json canonical_options(const Options& options) {
  return option_table<Options>().canonical(options);
}

}  // namespace khz::scene::detail
