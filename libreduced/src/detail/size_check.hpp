#pragma once
// The argument-size check of per-frame calls that take caller-presized vectors and matrices.

#include <khz/reduced/errors.hpp>

#include <Eigen/Core>

#include <string>

namespace khz::reduced::detail {

/// Throws Error "<what> has <actual> <unit>, expected <expected> (<rule>)" unless actual equals
/// expected, e.g. "q has 5 entries, expected 4 (one per basis column)".
inline void check_size(const char* what, const char* unit, Eigen::Index actual,
                       Eigen::Index expected, const char* rule) {
  if (actual != expected) {
    throw Error(std::string(what) + " has " + std::to_string(actual) + " " + unit + ", expected " +
                std::to_string(expected) + " (" + rule + ")");
  }
}

}  // namespace khz::reduced::detail
