#pragma once
// MPI return codes as reduced::Error.

#include <khz/reduced/errors.hpp>

#include <mpi.h>

#include <string>

namespace khz::mpi::detail {

/// Throws reduced::Error("<call>: <MPI's message>") unless `code` is MPI_SUCCESS.
inline void check(int code, const char* call) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw reduced::Error(std::string(call) + ": " +
                       std::string(text, static_cast<std::size_t>(length)));
}

}  // namespace khz::mpi::detail
