#include <khz/reduced/solvers/symmetric_factorization.hpp>

namespace khz::reduced {

SymmetricFactorization::~SymmetricFactorization() = default;

}  // namespace khz::reduced
