#include "analysis/psignifit_sigmoid.h"

#include <boost/math/special_functions/erf.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace glarelab::analysis {

namespace {

// Every sigmoid of Schütt et al. (2016, Table 1) is an increasing standard form G evaluated at
//   z = C (x - m) / w + G^-1(PC),  C = G^-1(1 - alpha) - G^-1(alpha),
// so that F(m) = PC and F^-1(1 - alpha) - F^-1(alpha) = w.
enum class StandardForm { normal, logistic, gumbel, reversed_gumbel, cauchy };

StandardForm standard_form(PsignifitSigmoid sigmoid) {
  switch (sigmoid) {
    case PsignifitSigmoid::norm:
    case PsignifitSigmoid::logn: return StandardForm::normal;
    case PsignifitSigmoid::logistic: return StandardForm::logistic;
    case PsignifitSigmoid::gumbel:
    case PsignifitSigmoid::weibull: return StandardForm::gumbel;
    case PsignifitSigmoid::rgumbel: return StandardForm::reversed_gumbel;
    case PsignifitSigmoid::tdist: return StandardForm::cauchy;
  }
  return StandardForm::normal;
}

// G(z). The normal form goes through erfc so that its lower tail keeps its relative precision.
double standard_cdf(StandardForm form, double z) {
  switch (form) {
    case StandardForm::normal: return 0.5 * std::erfc(-z / std::numbers::sqrt2);
    case StandardForm::logistic: return 1.0 / (1.0 + std::exp(-z));
    case StandardForm::gumbel: return 1.0 - std::exp(-std::exp(z));       // minimum extreme value
    case StandardForm::reversed_gumbel: return std::exp(-std::exp(-z));   // maximum extreme value
    case StandardForm::cauchy: return 0.5 + std::atan(z) / std::numbers::pi;  // Student t, 1 df
  }
  return 0.0;
}

double standard_pdf(StandardForm form, double z) {
  switch (form) {
    case StandardForm::normal: return std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
    case StandardForm::logistic: {
      const double g = 1.0 / (1.0 + std::exp(-z));
      return g * (1.0 - g);
    }
    case StandardForm::gumbel: return std::exp(z - std::exp(z));
    case StandardForm::reversed_gumbel: return std::exp(-z - std::exp(-z));
    case StandardForm::cauchy: return 1.0 / (std::numbers::pi * (1.0 + z * z));
  }
  return 0.0;
}

double standard_quantile(StandardForm form, double p) {
  switch (form) {
    case StandardForm::normal: return -std::numbers::sqrt2 * boost::math::erfc_inv(2.0 * p);
    case StandardForm::logistic: return std::log(p / (1.0 - p));
    case StandardForm::gumbel: return std::log(-std::log(1.0 - p));
    case StandardForm::reversed_gumbel: return -std::log(-std::log(p));
    case StandardForm::cauchy: return std::tan(std::numbers::pi * (p - 0.5));
  }
  return 0.0;
}

}  // namespace

std::optional<PsignifitSigmoid> psignifit_sigmoid_from_name(std::string_view name) {
  if (name == "norm" || name == "gauss") return PsignifitSigmoid::norm;
  if (name == "logistic") return PsignifitSigmoid::logistic;
  if (name == "gumbel") return PsignifitSigmoid::gumbel;
  if (name == "rgumbel") return PsignifitSigmoid::rgumbel;
  if (name == "tdist" || name == "student" || name == "heavytail") return PsignifitSigmoid::tdist;
  if (name == "Weibull" || name == "weibull") return PsignifitSigmoid::weibull;
  if (name == "logn") return PsignifitSigmoid::logn;
  return std::nullopt;
}

std::string psignifit_sigmoid_name(PsignifitSigmoid sigmoid) {
  switch (sigmoid) {
    case PsignifitSigmoid::norm: return "norm";
    case PsignifitSigmoid::logistic: return "logistic";
    case PsignifitSigmoid::gumbel: return "gumbel";
    case PsignifitSigmoid::rgumbel: return "rgumbel";
    case PsignifitSigmoid::tdist: return "tdist";
    case PsignifitSigmoid::weibull: return "Weibull";
    case PsignifitSigmoid::logn: return "logn";
  }
  return "norm";
}

std::string psignifit_sigmoid_names() { return "norm, logistic, gumbel, rgumbel, tdist, Weibull, logn"; }

bool psignifit_log_space(PsignifitSigmoid sigmoid) {
  return sigmoid == PsignifitSigmoid::weibull || sigmoid == PsignifitSigmoid::logn;
}

PsignifitSigmoidCurve::PsignifitSigmoidCurve(PsignifitSigmoid sigmoid, double thresh_pc, double width_alpha)
    : sigmoid_(sigmoid) {
  if (!(thresh_pc > 0.0 && thresh_pc < 1.0))
    throw std::invalid_argument("threshPC must lie strictly between 0 and 1, not " + std::to_string(thresh_pc));
  if (!(width_alpha > 0.0 && width_alpha < 0.5))
    throw std::invalid_argument("widthalpha must lie strictly between 0 and 0.5, not " + std::to_string(width_alpha));
  const StandardForm form = standard_form(sigmoid);
  scale_ = standard_quantile(form, 1.0 - width_alpha) - standard_quantile(form, width_alpha);
  offset_ = standard_quantile(form, thresh_pc);
}

double PsignifitSigmoidCurve::operator()(double x, double threshold, double width) const {
  return standard_cdf(standard_form(sigmoid_), scale_ * (x - threshold) / width + offset_);
}

double PsignifitSigmoidCurve::inverse(double p, double threshold, double width) const {
  return threshold + width * (standard_quantile(standard_form(sigmoid_), p) - offset_) / scale_;
}

double PsignifitSigmoidCurve::derivative(double x, double threshold, double width) const {
  return standard_pdf(standard_form(sigmoid_), scale_ * (x - threshold) / width + offset_) * scale_ / width;
}

}  // namespace glarelab::analysis
