#pragma once
// The sigmoids of psignifit 4 (Schütt, Harmeling, Macke & Wichmann 2016, "Painfree and accurate
// Bayesian estimation of psychometric functions for (potentially) overdispersed data", Vision
// Research 122, 105-123, section 2.1 and Table 1), parameterised by threshold m and width w:
//   F(m) = PC (the threshold's proportion of the unscaled sigmoid, threshPC, 0.5 by default),
//   w = F^-1(1 - alpha) - F^-1(alpha) (the width between the alpha and 1 - alpha points, alpha =
//   widthalpha, 0.05 by default).
// Weibull and logn are gumbel and norm on the natural log of the stimulus level: the fit works on
// log levels for them, so their threshold and width are in log units.
#include <optional>
#include <string>
#include <string_view>

namespace glarelab::analysis {

enum class PsignifitSigmoid { norm, logistic, gumbel, rgumbel, tdist, weibull, logn };

// psignifit's names (sigmoidName): norm (or gauss), logistic, gumbel, rgumbel, tdist (or student,
// heavytail), Weibull (or weibull), logn; nullopt for any other.
std::optional<PsignifitSigmoid> psignifit_sigmoid_from_name(std::string_view name);
std::string psignifit_sigmoid_name(PsignifitSigmoid sigmoid);
// The names accepted, for messages: "norm, logistic, ...".
std::string psignifit_sigmoid_names();
// Weibull and logn: fitted on the natural log of the stimulus level.
bool psignifit_log_space(PsignifitSigmoid sigmoid);

// F(x; m, w) for one sigmoid, PC and alpha, with x on the fitted axis (the log level for Weibull
// and logn). The constants of the parameterisation are computed once.
class PsignifitSigmoidCurve {
 public:
  PsignifitSigmoidCurve(PsignifitSigmoid sigmoid, double thresh_pc, double width_alpha);
  double operator()(double x, double threshold, double width) const;
  // The level where F = p (0 < p < 1), on the fitted axis.
  double inverse(double p, double threshold, double width) const;
  // dF/dx at x, on the fitted axis.
  double derivative(double x, double threshold, double width) const;
  PsignifitSigmoid sigmoid() const { return sigmoid_; }

 private:
  PsignifitSigmoid sigmoid_;
  double scale_ = 0.0;   // C: the width of the standard form between its alpha and 1 - alpha points
  double offset_ = 0.0;  // the standard form's argument where it equals PC
};

}  // namespace glarelab::analysis
