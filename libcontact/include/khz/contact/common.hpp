#pragma once
// What libcontact shares with libreduced: its exception types and progress reporting (one
// hierarchy to catch for every Kilohertz set-up failure), and the point and mesh containers.

#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/progress.hpp>

namespace khz::contact {

using reduced::Cancelled;
using reduced::Error;
using reduced::IoError;
using reduced::MeshError;
using reduced::ParseError;
using reduced::SolverError;

using reduced::Progress;
using reduced::ProgressCallback;

using reduced::TriangleMatrix;
using reduced::TriangleMesh;
/// N×3 points or vectors (metres, or unit vectors), one per row, contiguous per point.
using PointMatrix = reduced::VertexMatrix;

}  // namespace khz::contact
