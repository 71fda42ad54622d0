#pragma once
// The JSON names of the enumerations a scene chooses between, shared by the reader and the
// content keys (which must spell them as the scene file does).

#include "json_reader.hpp"

#include <khz/contact/query/contact_options.hpp>
#include <khz/haptic/device/trajectory_device.hpp>
#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/scene/anchor_region.hpp>
#include <khz/scene/basis_description.hpp>
#include <khz/scene/device_description.hpp>
#include <khz/scene/model_description.hpp>
#include <khz/scene/pointshell_description.hpp>

#include <array>

namespace khz::scene::detail {

inline constexpr std::array<Named<ModelType>, 2> model_types{{
    {"rigid", ModelType::rigid},
    {"reduced", ModelType::reduced},
}};

inline constexpr std::array<Named<MeshingMethod>, 2> meshing_methods{{
    {"voxels", MeshingMethod::voxels},
    {"tetrahedra", MeshingMethod::tetrahedra},
}};

inline constexpr std::array<Named<BasisMethod>, 3> basis_methods{{
    {"modes", BasisMethod::modes},
    {"sketch", BasisMethod::sketch},
    {"simulation_data", BasisMethod::simulation_data},
}};

inline constexpr std::array<Named<reduced::MassLumping>, 2> mass_lumpings{{
    {"consistent", reduced::MassLumping::consistent},
    {"lumped", reduced::MassLumping::lumped},
}};

inline constexpr std::array<Named<reduced::PcaMetric>, 3> pca_metrics{{
    {"mass", reduced::PcaMetric::mass},
    {"lumped_mass", reduced::PcaMetric::lumped_mass},
    {"euclidean", reduced::PcaMetric::euclidean},
}};

inline constexpr std::array<Named<AnchorRegion::Kind>, 2> anchor_kinds{{
    {"box", AnchorRegion::Kind::box},
    {"half_space", AnchorRegion::Kind::half_space},
}};

inline constexpr std::array<Named<PointshellMethod>, 4> pointshell_methods{{
    {"repulsion", PointshellMethod::repulsion},
    {"vertices", PointshellMethod::vertices},
    {"random", PointshellMethod::random},
    {"voxels", PointshellMethod::voxels},
}};

/// Object roles, which are also the two sides ContactOptions::haptic_object chooses between.
inline constexpr std::array<Named<contact::HapticObject>, 2> role_names{{
    {"pointshell", contact::HapticObject::pointshell},
    {"distance_field", contact::HapticObject::distance_field},
}};

inline constexpr std::array<Named<contact::ContactGradient>, 2> contact_gradients{{
    {"field_gradient", contact::ContactGradient::field_gradient},
    {"normal_direction", contact::ContactGradient::normal_direction},
}};

inline constexpr std::array<Named<contact::DegradationOptions::Mode>, 3> degradation_modes{{
    {"none", contact::DegradationOptions::Mode::none},
    {"node_count", contact::DegradationOptions::Mode::node_count},
    {"time_budget", contact::DegradationOptions::Mode::time_budget},
}};

inline constexpr std::array<Named<DeviceType>, 4> device_types{{
    {"null", DeviceType::null},
    {"trajectory", DeviceType::trajectory},
    {"operator", DeviceType::simulated_operator},
    {"hardware", DeviceType::hardware},
}};

inline constexpr std::array<Named<haptic::Playback>, 2> playbacks{{
    {"sample_per_read", haptic::Playback::sample_per_read},
    {"at_nominal_rate", haptic::Playback::at_nominal_rate},
}};

}  // namespace khz::scene::detail
