// A seeded psychometric observer for dry runs, pipeline tests and power estimates.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "protocols/adjustment_procedure.h"
#include "protocols/observer.h"
#include "core/random.h"

namespace glarelab {
namespace {

// Spread of log response time: sigma of ln(t). With 0.25 the middle 95 % of response times span
// about a factor of 2.7, typical of simple discrimination responses.
constexpr double kResponseTimeSigma = 0.25;

class SimulatedObserver : public Observer {
 public:
  SimulatedObserver(const SimulatedObserverSpec& spec, std::uint64_t seed)
      : spec_(spec), choice_random_(seed, RandomStream::observer), time_random_(seed, RandomStream::response_time) {}

  std::string description() const override { return "simulated"; }

  Response respond(const TrialPlan& plan) override {
    const bool choice = plan.adjustment_start_cd_m2.empty() && !plan.simulated_rating_mean;
    if (choice && (plan.allowed_responses.size() < 2 || plan.source_luminance_cd_m2.size() < 2)) {
      throw std::invalid_argument("simulated observer: trial " + std::to_string(plan.trial_index) +
                                  " needs two positions and at least two allowed responses");
    }
    if (plan.trial_index < 0) throw std::invalid_argument("simulated observer: negative trial index");
    const auto index = static_cast<std::uint64_t>(plan.trial_index);
    const double u = choice_random_.uniform(index);

    Response response;
    if (!plan.adjustment_start_cd_m2.empty()) {
      // A matching observer: each spot is set to the target's luminance (position 1) times
      // 10^(match_sd_log10 * N(0, 1)), independently per spot.
      const double target_cd_m2 = plan.source_luminance_cd_m2.at(1);
      response.value =
          format_adjustment_response(target_cd_m2 * std::pow(10.0, spec_.match_sd_log10 * choice_random_.normal(index, 0)),
                                     target_cd_m2 * std::pow(10.0, spec_.match_sd_log10 * choice_random_.normal(index, 1)));
    } else if (plan.simulated_rating_mean) {
      // A rating: the condition's mean plus Gaussian noise, rounded to the scale's points.
      const double rating = std::round(*plan.simulated_rating_mean + spec_.rating_sd * choice_random_.normal(index));
      const double top = static_cast<double>(plan.allowed_responses.size());
      response.value = plan.allowed_responses[static_cast<std::size_t>(std::clamp(rating, 1.0, top)) - 1];
    } else if (plan.appearance_judgement || glare_modes_judged(plan)) {
      response.value = appearance_response(plan, index);
    } else if (const std::optional<double> prefer_first = preference_for(plan); prefer_first && plan.correct_response.empty()) {
      // No right answer, two conditions with a stated preference: the first position's condition
      // is chosen with its preference probability (same uniform draw, so still one per trial).
      response.value = plan.allowed_responses[u < *prefer_first ? 0 : 1];
    } else if (plan.correct_response.empty()) {
      // No right answer: each allowed response is equally likely.
      const auto pick = static_cast<std::size_t>(u * static_cast<double>(plan.allowed_responses.size()));
      response.value = plan.allowed_responses[std::min(pick, plan.allowed_responses.size() - 1)];
    } else if (plan.allowed_responses.size() == 3) {
      // 3-way with "neither" (Spencer 1995): the observer names the brighter side when it sees a
      // difference, with probability (1 - 2 lapse) W(d) (the 2-AFC curve without its guessing
      // half), and otherwise answers the third response, "neither".
      const double d = log_ratio(plan.source_luminance_cd_m2[0], plan.source_luminance_cd_m2[1]);
      const std::string& neither = plan.allowed_responses[2];
      const bool seen = plan.correct_response != neither && u < (1.0 - 2.0 * spec_.lapse) * weibull(d);
      response.value = seen ? plan.correct_response : neither;
    } else {
      const double d = log_ratio(plan.source_luminance_cd_m2[0], plan.source_luminance_cd_m2[1]);
      if (u < p_correct(d)) {
        response.value = plan.correct_response;
      } else {
        for (const std::string& other : plan.allowed_responses) {
          if (other != plan.correct_response) {
            response.value = other;
            break;
          }
        }
      }
    }
    // Lognormal response time: ln t ~ N(ln median, sigma^2), so the median is exactly the spec's.
    response.response_time_s =
        spec_.response_time_median_s * std::exp(kResponseTimeSigma * time_random_.normal(index));
    return response;
  }

 private:
  // A PSE trial (Spencer et al. 1995, section 4): which side looks brighter. Perceived luminance
  // of a side: L (1 + k g), g its glare gain; the difference of perceived log10 luminances, with
  // Gaussian noise (the draw normal(index), independent of the choice's uniform draw), names the
  // brighter side beyond +-neither_band_log10 and is "neither" within it. A black side is
  // infinitely darker. P(position 0 named) = Phi((d - band) / sd) for true difference d, so the
  // answers are symmetric about d = 0: the point of subjective equality is L_ref (1 + k g_ref).
  std::string appearance_response(const TrialPlan& plan, std::uint64_t index) const {
    const auto perceived = [&](std::size_t p) {
      const double gain = p < plan.position_glare_gain.size() ? plan.position_glare_gain[p] : 0.0;
      return plan.source_luminance_cd_m2.at(p) * (1.0 + spec_.glare_brightening_per_gain * gain) *
             (1.0 + mode_brightening(plan, p));
    };
    const double a = perceived(0), b = perceived(1);
    double d = 0.0;
    if (a > 0.0 && b > 0.0) d = std::log10(a / b);
    else if (a != b) d = a > b ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
    const double seen = d + spec_.appearance_sd_log10 * choice_random_.normal(index);
    if (seen > spec_.neither_band_log10) return plan.allowed_responses[0];
    if (seen < -spec_.neither_band_log10) return plan.allowed_responses[1];
    if (plan.allowed_responses.size() >= 3) return plan.allowed_responses[2];
    return plan.allowed_responses[seen >= 0.0 ? 0 : 1];  // two answers: the sign decides
  }

  // A forced choice whose two sides carry glare modes (glare_a, glare_b) is an appearance
  // judgement when the observer is given a brightening per glare mode (SimulatedObserverSpec).
  bool glare_modes_judged(const TrialPlan& plan) const {
    return !spec_.glare_mode_brightening.empty() && plan.position_glare.size() == 2 &&
           plan.source_luminance_cd_m2.size() == 2;
  }

  // The brightening of the glare mode shown at position p (0 for modes not listed).
  double mode_brightening(const TrialPlan& plan, std::size_t p) const {
    if (p >= plan.position_glare.size()) return 0.0;
    const auto found = spec_.glare_mode_brightening.find(plan.position_glare[p]);
    return found == spec_.glare_mode_brightening.end() ? 0.0 : found->second;
  }

  // Probability of choosing position 0 over position 1 from the preferences between the two
  // conditions shown; nothing when the plan names no conditions or the pair has no preference.
  std::optional<double> preference_for(const TrialPlan& plan) const {
    if (plan.position_conditions.size() != 2) return std::nullopt;
    return preference_probability(spec_.preferences, plan.position_conditions[0], plan.position_conditions[1]);
  }

  // |log10(L_left / L_right)|: Weber-like discrimination depends on the luminance ratio.
  static double log_ratio(double left, double right) {
    if (left > 0.0 && right > 0.0) return std::abs(std::log10(left / right));
    // A dark source next to a lit one is an infinitely large ratio: certain but for lapses.
    return left == right ? 0.0 : std::numeric_limits<double>::infinity();
  }

  // Weibull psychometric function for two-alternative forced choice (Wichmann & Hill 2001,
  // "The psychometric function: I. Fitting, sampling, and goodness of fit", Perception &
  // Psychophysics 63(8), eq. 1):
  //   p(d) = gamma + (1 - gamma - lambda) * (1 - exp(-(d / alpha)^beta))
  // with guess rate gamma = 0.5 (2-AFC), lapse rate lambda, threshold alpha (log10 units) and
  // slope beta. p runs from chance (0.5) at d = 0 to 1 - lambda for large d.
  double weibull(double d) const { return 1.0 - std::exp(-std::pow(d / spec_.threshold_log10, spec_.slope)); }
  double p_correct(double d) const {
    constexpr double kGuess = 0.5;
    return kGuess + (1.0 - kGuess - spec_.lapse) * weibull(d);
  }

  SimulatedObserverSpec spec_;
  CounterRandom choice_random_;
  CounterRandom time_random_;
};

}  // namespace

std::unique_ptr<Observer> make_simulated_observer(const SimulatedObserverSpec& spec, std::uint64_t seed) {
  return std::make_unique<SimulatedObserver>(spec, seed);
}

}  // namespace glarelab
