#pragma once
// Full displacements and deformed vertex positions of the simulation mesh from reduced
// coordinates: u = U q (thesis §2.12), called once per rendered frame.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// u = U q (thesis §2.12): the full displacement of reduced coordinates q.
///
/// Per frame, not per haptic cycle: writes into the caller-presized `displacement`, allocates
/// nothing, and splits the rows over OpenMP threads when U is large enough to gain. The result
/// does not depend on the number of threads.
/// @param basis U, 3n×r (metres per unit of q), e.g. Basis::vectors or its first r′ columns (any
///        leading columns form a valid smaller model, §2.11).
/// @param q r reduced coordinates.
/// @param displacement 3n output (metres), vertex v at entries 3v … 3v+2.
/// @throws Error if q does not have r entries or `displacement` does not have 3n.
KHZ_REDUCED_API void reconstruct_displacement(const Eigen::Ref<const Eigen::MatrixXd>& basis,
                                              const Eigen::Ref<const Eigen::VectorXd>& q,
                                              Eigen::Ref<Eigen::VectorXd> displacement);

/// x = X + U q: deformed vertex positions as #V×3 rows, the layout of VertexMatrix that
/// renderers and the VTK writer take. Same cost, threading and allocation behaviour as
/// reconstruct_displacement(); `positions` must be contiguous (a VertexMatrix, or a Map of one
/// over a caller's buffer), which the stride in its type enforces at compile time.
/// @param rest X, #V×3 rest positions (metres), e.g. VolumeMesh::vertices.
/// @param basis U, 3#V×r.
/// @param q r reduced coordinates.
/// @param positions #V×3 output (metres); may be `rest` itself (x += U q in place).
/// @throws Error if `basis` does not have 3#V rows, q r entries, or `positions` #V rows.
KHZ_REDUCED_API void reconstruct_positions(
    const Eigen::Ref<const VertexMatrix>& rest, const Eigen::Ref<const Eigen::MatrixXd>& basis,
    const Eigen::Ref<const Eigen::VectorXd>& q,
    Eigen::Ref<VertexMatrix, 0, Eigen::OuterStride<3>> positions);

}  // namespace khz::reduced
