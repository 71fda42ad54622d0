#include <khz/reduced/subspace/reduced_forces.hpp>

namespace khz::reduced {

ReducedForceModel::~ReducedForceModel() = default;

}  // namespace khz::reduced
