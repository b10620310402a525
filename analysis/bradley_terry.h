#pragma once
// Bradley-Terry scaling of paired comparisons (Bradley & Terry 1952): item i is chosen over item j
// with probability pi_i / (pi_i + pi_j). The worths are fitted by maximum likelihood with the MM
// algorithm of Hunter (2004, "MM algorithms for generalized Bradley-Terry models", Ann. Statist.
// 32(1), Eq. 3):  pi_i <- W_i / sum_{j != i} n_ij / (pi_i + pi_j),  W_i the wins of i, n_ij the
// comparisons of i and j, which increases the likelihood at every step and converges whenever the
// MLE exists. The scale reported is lambda_i = ln pi_i - ln pi_ref (the reference item at 0), the
// parametrisation of Agresti (2002, Categorical Data Analysis, Sec. 10.6) and R's BradleyTerry2;
// standard errors from the inverse of the Fisher information of (lambda_i, i != ref):
//   I_ii = sum_j n_ij p_ij p_ji,   I_ij = -n_ij p_ij p_ji,   p_ij = pi_i / (pi_i + pi_j).
// The MLE exists (is finite) exactly when the graph "i beat j at least once" is strongly connected
// (Ford 1957; Hunter 2004, Assumption 1); otherwise no scale is given, with the reason.
#include <string>
#include <vector>

namespace glarelab::analysis {

struct BradleyTerryScale {
  std::string unavailable;               // non-empty: why there is no scale
  std::vector<std::string> items;
  std::size_t reference = 0;             // index of the item at 0
  std::vector<double> log_worth;         // lambda_i, lambda_ref = 0
  std::vector<double> standard_error;    // of lambda_i (0 for the reference)
  std::vector<double> worth;             // pi_i / pi_ref = exp(lambda_i)
  double log_likelihood = 0.0;
  int iterations = 0;
  bool ok() const { return unavailable.empty(); }
};

// wins[i][j]: how often item i was chosen over item j (the diagonal is ignored).
BradleyTerryScale fit_bradley_terry(const std::vector<std::string>& items, const std::vector<std::vector<long>>& wins,
                                    std::size_t reference = 0);

}  // namespace glarelab::analysis
