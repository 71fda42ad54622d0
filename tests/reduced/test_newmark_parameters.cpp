#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/newmark_parameters.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

namespace khz::reduced {
namespace {

TEST(NewmarkConstants, MatchTheNewmarkUpdateFormulas) {
  // Independent check: one step of u = u0 + h v0 + h²((½−β)a0 + β a1), v = v0 + h((1−γ)a0 + γ a1)
  // must be reproduced by a1 = α1 Δu − α2 v0 − α3 a0, v1 = α4 Δu + α5 v0 + α6 a0.
  NewmarkParameters p;
  p.time_step = 0.01;
  p.beta = 0.3;
  p.gamma = 0.6;
  const NewmarkConstants c = NewmarkConstants::from(p);
  const double h = p.time_step, v0 = 1.5, a0 = -2.0, a1 = 0.7;
  const double du = h * v0 + h * h * ((0.5 - p.beta) * a0 + p.beta * a1);
  const double v1 = v0 + h * ((1 - p.gamma) * a0 + p.gamma * a1);
  EXPECT_NEAR(c.alpha1 * du - c.alpha2 * v0 - c.alpha3 * a0, a1, 1e-12);
  EXPECT_NEAR(c.alpha4 * du + c.alpha5 * v0 + c.alpha6 * a0, v1, 1e-12);
}

TEST(NewmarkParameters, RejectsOutOfRangeValues) {
  NewmarkParameters p;
  p.time_step = 0;
  EXPECT_TRUE(test::throws_with_message<Error>([&] { p.validate(); }, "time_step"));
  p = {};
  p.gamma = 1.5;
  EXPECT_TRUE(test::throws_with_message<Error>([&] { p.validate(); }, "gamma"));
  p = {};
  p.stiffness_damping = -1;
  EXPECT_TRUE(test::throws_with_message<Error>([&] { p.validate(); }, "stiffness_damping"));
  p = {};
  p.beta = 0;  // explicit central differences: valid parameters, but not for an implicit solver
  EXPECT_NO_THROW(p.validate());
  EXPECT_TRUE(test::throws_with_message<Error>([&] { NewmarkConstants::from(p); },
                                               "positive for an implicit integrator"));
}

}  // namespace
}  // namespace khz::reduced
