// Bradley-Terry scaling (analysis/bradley_terry.h) against a published fit and a hand-worked one.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/bradley_terry.h"

namespace glarelab::analysis {
namespace {

// Stigler's (1994) inter-journal citations as Agresti (2002, Categorical Data Analysis, 2nd ed.,
// p. 448) fits them, and R's BradleyTerry2 (Turner & Firth 2012, J. Stat. Softw. 48(9), Sec. 2.1,
// `citeModel`): a citation of journal i by journal j is a win of i over j. Published log worths
// with Biometrika as the reference: Comm Statist -2.9491, JASA -0.4796, JRSS-B 0.2690.
TEST(AnalysisBradleyTerry, StiglerCitationsAsPublished) {
  const std::vector<std::string> journals = {"Biometrika", "Comm Statist", "JASA", "JRSS-B"};
  // wins[i][j]: journal i cited by journal j (the rows of Agresti's table are the cited journal).
  const std::vector<std::vector<long>> wins = {
      {714, 730, 498, 221}, {33, 425, 68, 17}, {320, 813, 1072, 142}, {284, 276, 325, 188}};
  const BradleyTerryScale scale = fit_bradley_terry(journals, wins, 0);
  ASSERT_TRUE(scale.ok()) << scale.unavailable;
  EXPECT_DOUBLE_EQ(scale.log_worth[0], 0.0);
  EXPECT_NEAR(scale.log_worth[1], -2.9491, 5e-5);
  EXPECT_NEAR(scale.log_worth[2], -0.4796, 5e-5);
  EXPECT_NEAR(scale.log_worth[3], 0.2690, 5e-5);

  // The standard errors against the curvature of the log likelihood, computed here on its own:
  // central second differences of ln L(lambda) = sum w_ij (lambda_i - ln(e^lambda_i + e^lambda_j))
  // at the fitted lambda, inverted (3 x 3, by cofactors).
  const auto log_likelihood = [&](const std::vector<double>& lambda) {
    double sum = 0.0;
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j)
        if (i != j) sum += static_cast<double>(wins[i][j]) * (lambda[i] - std::log(std::exp(lambda[i]) + std::exp(lambda[j])));
    return sum;
  };
  const double h = 1e-4;
  double hessian[3][3];
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      double value = 0.0;
      for (int sa : {-1, 1}) {
        for (int sb : {-1, 1}) {
          std::vector<double> lambda = scale.log_worth;
          lambda[a + 1] += sa * h;
          lambda[b + 1] += sb * h;
          value += sa * sb * log_likelihood(lambda);
        }
      }
      hessian[a][b] = -value / (4.0 * h * h);  // the observed information
    }
  }
  const auto cofactor = [&](int r, int c) {
    const int r0 = r == 0 ? 1 : 0, r1 = r == 2 ? 1 : 2, c0 = c == 0 ? 1 : 0, c1 = c == 2 ? 1 : 2;
    return hessian[r0][c0] * hessian[r1][c1] - hessian[r0][c1] * hessian[r1][c0];
  };
  const double determinant = hessian[0][0] * cofactor(0, 0) - hessian[0][1] * cofactor(0, 1) + hessian[0][2] * cofactor(0, 2);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(scale.standard_error[a + 1], std::sqrt(cofactor(a, a) / determinant), 1e-5) << journals[a + 1];
  // The same standard errors rounded (the table printed by BradleyTerry2's summary(citeModel)).
  EXPECT_NEAR(scale.standard_error[1], 0.1025, 1e-4);
  EXPECT_NEAR(scale.standard_error[2], 0.0606, 1e-4);
  EXPECT_NEAR(scale.standard_error[3], 0.0708, 1e-4);
}

// Three items whose counts equal the expected counts of worths 1 : 2 : 4 (30 comparisons per
// pair: 10-20, 6-24, 10-20) satisfy the likelihood equations W_i = sum_j n_ij pi_i / (pi_i + pi_j)
// exactly, so the MLE is lambda = (0, ln 2, ln 4). Fisher information of (lambda_2, lambda_3),
// with n p (1 - p) = 30 (1/3)(2/3) = 20/3 for pairs 1-2 and 2-3 and 30 (1/5)(4/5) = 24/5 for 1-3:
//   I = [[40/3, -20/3], [-20/3, 172/15]],  det = 976/9,
//   var lambda_2 = (172/15) / (976/9) = 1548/14640,  var lambda_3 = (40/3) / (976/9) = 360/2928.
TEST(AnalysisBradleyTerry, ThreeItemsWorkedByHand) {
  const std::vector<std::vector<long>> wins = {{0, 10, 6}, {20, 0, 10}, {24, 20, 0}};
  const BradleyTerryScale scale = fit_bradley_terry({"control", "static", "dynamic"}, wins, 0);
  ASSERT_TRUE(scale.ok()) << scale.unavailable;
  EXPECT_NEAR(scale.log_worth[1], std::log(2.0), 1e-10);
  EXPECT_NEAR(scale.log_worth[2], std::log(4.0), 1e-10);
  EXPECT_NEAR(scale.worth[2], 4.0, 1e-9);
  EXPECT_NEAR(scale.standard_error[1], std::sqrt(1548.0 / 14640.0), 1e-9);
  EXPECT_NEAR(scale.standard_error[2], std::sqrt(360.0 / 2928.0), 1e-9);
  EXPECT_EQ(scale.standard_error[0], 0.0);
  // ln L = 10 ln(1/3) + 20 ln(2/3) + 6 ln(1/5) + 24 ln(4/5) + 10 ln(1/3) + 20 ln(2/3).
  EXPECT_NEAR(scale.log_likelihood,
              20 * std::log(1.0 / 3) + 40 * std::log(2.0 / 3) + 6 * std::log(0.2) + 24 * std::log(0.8), 1e-9);
  // Another reference moves every value by the same constant, and the SE of the old reference is
  // that of lambda_3 - lambda_1 seen from item 3.
  const BradleyTerryScale from_dynamic = fit_bradley_terry({"control", "static", "dynamic"}, wins, 2);
  ASSERT_TRUE(from_dynamic.ok());
  EXPECT_NEAR(from_dynamic.log_worth[0], -std::log(4.0), 1e-10);
  EXPECT_NEAR(from_dynamic.standard_error[0], scale.standard_error[2], 1e-9);
}

// No finite MLE: an item that never lost (or never won), or items never compared across groups.
TEST(AnalysisBradleyTerry, NoScaleWithoutAStronglyConnectedWinGraph) {
  EXPECT_FALSE(fit_bradley_terry({"a", "b", "c"}, {{0, 5, 4}, {0, 0, 3}, {0, 2, 0}}).ok());  // a never lost
  EXPECT_FALSE(fit_bradley_terry({"a", "b", "c", "d"}, {{0, 2, 0, 0}, {3, 0, 0, 0}, {0, 0, 0, 1}, {0, 0, 1, 0}}).ok());
  EXPECT_TRUE(fit_bradley_terry({"a", "b"}, {{0, 3}, {1, 0}}).ok());
  // Two items: lambda_b = ln(wins of b / wins of a) exactly, SE = sqrt(1/3 + 1/1).
  const BradleyTerryScale two = fit_bradley_terry({"a", "b"}, {{0, 3}, {1, 0}});
  EXPECT_NEAR(two.log_worth[1], std::log(1.0 / 3.0), 1e-10);
  EXPECT_NEAR(two.standard_error[1], std::sqrt(1.0 / 3.0 + 1.0), 1e-9);
}

}  // namespace
}  // namespace glarelab::analysis
