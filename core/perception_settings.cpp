#include "core/perception_settings.h"

#include <stdexcept>

namespace glarelab {
namespace {

[[noreturn]] void refuse(const char* field, const std::string& text, const char* accepted) {
  throw std::invalid_argument(std::string("perception settings: ") + field + " must be one of " + accepted +
                              " (got '" + text + "')");
}

}  // namespace

ToneCurve parse_tone_curve(const std::string& text) {
  if (text == "aces_narkowicz") return ToneCurve::aces_narkowicz;
  if (text == "aces_hill") return ToneCurve::aces_hill;
  if (text == "none") return ToneCurve::none;
  refuse("tone_curve", text, "\"aces_narkowicz\", \"aces_hill\", \"none\"");
}

ScotopicForm parse_scotopic_form(const std::string& text) {
  if (text == "luidolt_tint") return ScotopicForm::luidolt_tint;
  if (text == "spencer_desaturation") return ScotopicForm::spencer_desaturation;
  refuse("scotopic_form", text, "\"luidolt_tint\", \"spencer_desaturation\"");
}

AcuitySigmaForm parse_acuity_sigma_form(const std::string& text) {
  if (text == "resolvable_frequency") return AcuitySigmaForm::resolvable_frequency;
  if (text == "luidolt_linear") return AcuitySigmaForm::luidolt_linear;
  refuse("acuity_sigma", text, "\"resolvable_frequency\", \"luidolt_linear\"");
}

SecondPassSigma parse_second_pass_sigma(const std::string& text) {
  if (text == "filtered_lightness") return SecondPassSigma::filtered_lightness;
  if (text == "original_lightness") return SecondPassSigma::original_lightness;
  refuse("acuity_second_pass", text, "\"filtered_lightness\", \"original_lightness\"");
}

std::string to_string(ToneCurve curve) {
  switch (curve) {
    case ToneCurve::aces_narkowicz: return "aces_narkowicz";
    case ToneCurve::aces_hill: return "aces_hill";
    case ToneCurve::none: return "none";
  }
  return "none";
}

std::string to_string(ScotopicForm form) {
  return form == ScotopicForm::luidolt_tint ? "luidolt_tint" : "spencer_desaturation";
}

std::string to_string(AcuitySigmaForm form) {
  return form == AcuitySigmaForm::resolvable_frequency ? "resolvable_frequency" : "luidolt_linear";
}

std::string to_string(SecondPassSigma pass) {
  return pass == SecondPassSigma::filtered_lightness ? "filtered_lightness" : "original_lightness";
}

}  // namespace glarelab
