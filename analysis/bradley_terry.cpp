#include "analysis/bradley_terry.h"

#include <algorithm>
#include <cmath>

namespace glarelab::analysis {
namespace {

constexpr int kMaxIterations = 100000;
constexpr double kTolerance = 1e-13;  // largest relative change of a worth in one step

// Every item reaches every other along "beat" edges: the condition for a finite MLE.
bool strongly_connected(const std::vector<std::vector<long>>& wins) {
  const std::size_t k = wins.size();
  for (int direction = 0; direction < 2; ++direction) {
    std::vector<bool> reached(k, false);
    std::vector<std::size_t> stack = {0};
    reached[0] = true;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      for (std::size_t j = 0; j < k; ++j) {
        const long edge = direction == 0 ? wins[i][j] : wins[j][i];
        if (i != j && edge > 0 && !reached[j]) {
          reached[j] = true;
          stack.push_back(j);
        }
      }
    }
    if (std::find(reached.begin(), reached.end(), false) != reached.end()) return false;
  }
  return true;
}

// Inverse of a small symmetric positive-definite matrix by Gauss-Jordan elimination with partial
// pivoting; false when it is singular.
bool invert(std::vector<std::vector<double>>& a) {
  const std::size_t n = a.size();
  std::vector<std::vector<double>> inverse(n, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < n; ++i) inverse[i][i] = 1.0;
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t pivot = c;
    for (std::size_t r = c + 1; r < n; ++r)
      if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
    if (!(std::abs(a[pivot][c]) > 1e-300)) return false;
    std::swap(a[c], a[pivot]);
    std::swap(inverse[c], inverse[pivot]);
    const double scale = a[c][c];
    for (std::size_t j = 0; j < n; ++j) {
      a[c][j] /= scale;
      inverse[c][j] /= scale;
    }
    for (std::size_t r = 0; r < n; ++r) {
      if (r == c || a[r][c] == 0.0) continue;
      const double factor = a[r][c];
      for (std::size_t j = 0; j < n; ++j) {
        a[r][j] -= factor * a[c][j];
        inverse[r][j] -= factor * inverse[c][j];
      }
    }
  }
  a = std::move(inverse);
  return true;
}

}  // namespace

BradleyTerryScale fit_bradley_terry(const std::vector<std::string>& items, const std::vector<std::vector<long>>& wins,
                                    std::size_t reference) {
  BradleyTerryScale scale;
  scale.items = items;
  scale.reference = reference;
  const std::size_t k = items.size();
  if (k < 2 || wins.size() != k || reference >= k) {
    scale.unavailable = "fewer than two items";
    return scale;
  }
  for (const auto& row : wins) {
    if (row.size() != k) {
      scale.unavailable = "the win table is not square";
      return scale;
    }
  }
  if (!strongly_connected(wins)) {
    scale.unavailable =
        "no finite scale: some items were never chosen over (or never lost to) the others they met, or not every item "
        "was compared with the rest (Ford 1957)";
    return scale;
  }
  std::vector<double> total_wins(k, 0.0);
  std::vector<std::vector<double>> n(k, std::vector<double>(k, 0.0));
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = 0; j < k; ++j) {
      if (i == j) continue;
      total_wins[i] += static_cast<double>(wins[i][j]);
      n[i][j] = static_cast<double>(wins[i][j] + wins[j][i]);
    }
  }
  std::vector<double> pi(k, 1.0);
  for (scale.iterations = 1; scale.iterations <= kMaxIterations; ++scale.iterations) {
    // Hunter (2004), Eq. 3, cyclic over the items, then normalised to a geometric mean of 1.
    double change = 0.0;
    for (std::size_t i = 0; i < k; ++i) {
      double denominator = 0.0;
      for (std::size_t j = 0; j < k; ++j)
        if (j != i && n[i][j] > 0.0) denominator += n[i][j] / (pi[i] + pi[j]);
      const double updated = total_wins[i] / denominator;
      change = std::max(change, std::abs(updated - pi[i]) / pi[i]);
      pi[i] = updated;
    }
    double log_mean = 0.0;
    for (double value : pi) log_mean += std::log(value) / static_cast<double>(k);
    for (double& value : pi) value /= std::exp(log_mean);
    if (change < kTolerance) break;
  }
  if (scale.iterations > kMaxIterations) {
    scale.unavailable = "the MM iteration did not converge";
    return scale;
  }
  for (std::size_t i = 0; i < k; ++i) {
    scale.log_worth.push_back(std::log(pi[i] / pi[reference]));
    scale.worth.push_back(pi[i] / pi[reference]);
    for (std::size_t j = 0; j < k; ++j) {
      if (j == i || wins[i][j] == 0) continue;
      scale.log_likelihood += static_cast<double>(wins[i][j]) * std::log(pi[i] / (pi[i] + pi[j]));
    }
  }
  // Fisher information of the non-reference log worths, then its inverse.
  std::vector<std::size_t> free;
  for (std::size_t i = 0; i < k; ++i)
    if (i != reference) free.push_back(i);
  std::vector<std::vector<double>> information(free.size(), std::vector<double>(free.size(), 0.0));
  for (std::size_t a = 0; a < free.size(); ++a) {
    const std::size_t i = free[a];
    for (std::size_t j = 0; j < k; ++j) {
      if (j == i) continue;
      const double p = pi[i] / (pi[i] + pi[j]);
      information[a][a] += n[i][j] * p * (1.0 - p);
    }
    for (std::size_t b = 0; b < free.size(); ++b) {
      const std::size_t j = free[b];
      if (b == a) continue;
      const double p = pi[i] / (pi[i] + pi[j]);
      information[a][b] = -n[i][j] * p * (1.0 - p);
    }
  }
  if (!invert(information)) {
    scale.unavailable = "the information matrix is singular";
    return scale;
  }
  scale.standard_error.assign(k, 0.0);
  for (std::size_t a = 0; a < free.size(); ++a) scale.standard_error[free[a]] = std::sqrt(information[a][a]);
  return scale;
}

}  // namespace glarelab::analysis
