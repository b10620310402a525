#include "analysis/psignifit_io.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "core/errors.h"

namespace glarelab::analysis {

namespace {

using nlohmann::json;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError({path, 0, 0}, "", "cannot open the file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

// Where each top-level key of a JSON object starts (1-based line and column), found by a scan
// that follows strings and nesting, since the JSON library keeps no positions.
std::map<std::string, std::pair<int, int>> top_level_key_positions(const std::string& text) {
  std::map<std::string, std::pair<int, int>> positions;
  int line = 1, column = 1, depth = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {
      const int start_line = line, start_column = column;
      std::string value;
      std::size_t j = i + 1;
      for (; j < text.size() && text[j] != '"'; ++j) {
        if (text[j] == '\\' && j + 1 < text.size()) ++j;
        value += text[j];
      }
      column += static_cast<int>(j - i) + 1;
      i = j;
      std::size_t k = i + 1;
      while (k < text.size() && (text[k] == ' ' || text[k] == '\t' || text[k] == '\r' || text[k] == '\n')) ++k;
      if (depth == 1 && k < text.size() && text[k] == ':' && !positions.contains(value)) positions[value] = {start_line, start_column};
      continue;
    }
    if (c == '{' || c == '[') ++depth;
    if (c == '}' || c == ']') --depth;
    if (c == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return positions;
}

class OptionReader {
 public:
  OptionReader(const std::string& text, std::string file) : file_(std::move(file)), positions_(top_level_key_positions(text)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    const auto found = positions_.find(key);
    const auto [line, column] = found == positions_.end() ? std::pair<int, int>{0, 0} : found->second;
    throw ConfigError({file_, line, column}, key, message);
  }
  double number(const std::string& key, const json& value) const {
    if (!value.is_number()) fail(key, "must be a number");
    return value.get<double>();
  }
  int integer(const std::string& key, const json& value) const {
    if (!value.is_number_integer() && !(value.is_number() && std::floor(value.get<double>()) == value.get<double>()))
      fail(key, "must be a whole number");
    return static_cast<int>(value.get<double>());
  }
  // A number, or null for "no limit" (psignifit's Inf).
  double limit(const std::string& key, const json& value) const {
    if (value.is_null()) return std::numeric_limits<double>::infinity();
    return number(key, value);
  }
  std::array<int, kPsignifitParameters> five_integers(const std::string& key, const json& value) const {
    if (!value.is_array() || value.size() != kPsignifitParameters) fail(key, "must be a list of 5 whole numbers");
    std::array<int, kPsignifitParameters> out{};
    for (int p = 0; p < kPsignifitParameters; ++p) {
      out[p] = integer(key, value[p]);
      if (out[p] < 1) fail(key, "needs at least one point per parameter");
    }
    return out;
  }

 private:
  std::string file_;
  std::map<std::string, std::pair<int, int>> positions_;
};

void read_option(PsignifitOptions& options, const OptionReader& reader, const std::string& key, const json& value) {
  if (key == "expType") {
    const std::string type = value.is_string() ? value.get<std::string>() : "";
    if (type == "YesNo") options.experiment = PsignifitExperiment::yes_no;
    else if (type == "equalAsymptote") options.experiment = PsignifitExperiment::equal_asymptote;
    else if (type == "nAFC") options.experiment = PsignifitExperiment::n_afc;
    else if (type == "2AFC" || type == "3AFC" || type == "4AFC") {
      options.experiment = PsignifitExperiment::n_afc;
      options.alternatives = type[0] - '0';
    } else reader.fail(key, "must be one of YesNo, 2AFC, 3AFC, 4AFC, nAFC, equalAsymptote");
  } else if (key == "expN") {
    if (!value.is_null()) options.alternatives = reader.integer(key, value);
    if (options.alternatives < 2) reader.fail(key, "must be at least 2 (the number of alternatives)");
  } else if (key == "sigmoidName") {
    const auto sigmoid = value.is_string() ? psignifit_sigmoid_from_name(value.get<std::string>()) : std::nullopt;
    if (!sigmoid) reader.fail(key, "must be one of " + psignifit_sigmoid_names());
    options.sigmoid = *sigmoid;
  } else if (key == "threshPC") {
    options.thresh_pc = reader.number(key, value);
    if (!(options.thresh_pc > 0.0 && options.thresh_pc < 1.0)) reader.fail(key, "must lie strictly between 0 and 1");
  } else if (key == "widthalpha") {
    options.width_alpha = reader.number(key, value);
    if (!(options.width_alpha > 0.0 && options.width_alpha < 0.5)) reader.fail(key, "must lie strictly between 0 and 0.5");
  } else if (key == "betaPrior") {
    options.beta_prior = reader.number(key, value);
    if (!(options.beta_prior >= 1.0)) reader.fail(key, "must be at least 1 (eta's prior is Beta(1, betaPrior))");
  } else if (key == "estimateType") {
    const std::string type = value.is_string() ? value.get<std::string>() : "";
    if (type != "MAP" && type != "mean") reader.fail(key, "must be MAP or mean");
    options.estimate_map = type == "MAP";
  } else if (key == "fixedPars") {
    if (!value.is_array() || value.size() != kPsignifitParameters) reader.fail(key, "must be a list of 5 entries, null for a free parameter");
    for (int p = 0; p < kPsignifitParameters; ++p)
      options.fixed[p] = value[p].is_null() ? std::nullopt : std::optional<double>(reader.number(key, value[p]));
  } else if (key == "confP") {
    options.credibility.clear();
    if (value.is_array()) {
      for (const json& entry : value) options.credibility.push_back(reader.number(key, entry));
    } else {
      options.credibility.push_back(reader.number(key, value));
    }
    if (options.credibility.empty()) reader.fail(key, "needs at least one credibility");
    for (double p : options.credibility)
      if (!(p > 0.0 && p < 1.0)) reader.fail(key, "credibilities must lie strictly between 0 and 1");
  } else if (key == "poolxTol") {
    options.pool_x_tol = reader.number(key, value);
    if (options.pool_x_tol < 0.0) reader.fail(key, "must not be negative");
  } else if (key == "poolMaxGap") {
    options.pool_max_gap = reader.limit(key, value);
  } else if (key == "poolMaxLength") {
    options.pool_max_length = reader.limit(key, value);
  } else if (key == "nblocks") {
    options.max_blocks = reader.integer(key, value);
    if (options.max_blocks < 1) reader.fail(key, "must be at least 1");
  } else if (key == "stimulusRange") {
    if (value.is_null() || (value.is_number() && value.get<double>() == 0.0)) options.stimulus_range.reset();
    else if (value.is_array() && value.size() == 2) options.stimulus_range = std::array<double, 2>{reader.number(key, value[0]), reader.number(key, value[1])};
    else reader.fail(key, "must be [low, high] in stimulus units, or null for the data's range");
  } else if (key == "stepN") {
    options.grid_steps = reader.five_integers(key, value);
  } else if (key == "mbStepN") {
    options.border_steps = reader.five_integers(key, value);
  } else if (key == "maxBorderValue") {
    options.max_border_value = reader.number(key, value);
    if (!(options.max_border_value > 0.0 && options.max_border_value < 1.0)) reader.fail(key, "must lie strictly between 0 and 1");
  } else if (key == "moveBorders") {
    if (!value.is_boolean() && !value.is_number()) reader.fail(key, "must be true or false");
    options.move_borders = value.is_boolean() ? value.get<bool>() : value.get<double>() != 0.0;
  } else if (key == "theta0") {
    if (!value.is_array() || value.size() != kPsignifitParameters) reader.fail(key, "must be a list of 5 numbers");
    PsignifitParameters theta{};
    for (int p = 0; p < kPsignifitParameters; ++p) theta[p] = reader.number(key, value[p]);
    options.generating_parameters = theta;
  } else {
    reader.fail(key, "unknown option (known: " + [] {
      std::string names;
      for (const std::string& name : psignifit_option_names()) names += (names.empty() ? "" : ", ") + name;
      return names;
    }() + ")");
  }
}

}  // namespace

std::vector<PsignifitBlock> parse_psignifit_data(const std::string& text, const std::string& file_name) {
  std::vector<PsignifitBlock> blocks;
  std::istringstream lines(text);
  std::string line;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    const std::string row = trim(line);
    if (row.empty() || row[0] == '#') continue;
    if (blocks.empty() && row == "level,correct,trials") continue;
    std::vector<std::string> cells;
    std::stringstream cells_in(row);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(trim(cell));
    if (cells.size() != 3) throw ConfigError({file_name, line_number, 1}, "", "expected 3 columns level,correct,trials, found " + std::to_string(cells.size()));
    double values[3] = {0.0, 0.0, 0.0};
    static const char* const kColumns[3] = {"level", "correct", "trials"};
    int column = 1;
    for (int c = 0; c < 3; ++c) {
      std::size_t used = 0;
      try {
        values[c] = std::stod(cells[c], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != cells[c].size() || !std::isfinite(values[c]))
        throw ConfigError({file_name, line_number, column}, kColumns[c], "'" + cells[c] + "' is not a number");
      if (c > 0 && (values[c] < 0.0 || std::floor(values[c]) != values[c]))
        throw ConfigError({file_name, line_number, column}, kColumns[c], "'" + cells[c] + "' is not a whole number of trials");
      column += static_cast<int>(cells[c].size()) + 1;
    }
    if (values[2] < 1.0 || values[1] > values[2])
      throw ConfigError({file_name, line_number, 1}, "", "a block needs at least one trial and no more correct answers than trials");
    blocks.push_back({values[0], static_cast<long>(values[1]), static_cast<long>(values[2])});
  }
  if (blocks.empty()) throw ConfigError({file_name, 0, 0}, "", "no data rows (level,correct,trials)");
  return blocks;
}

std::vector<PsignifitBlock> read_psignifit_data(const std::string& path) { return parse_psignifit_data(read_text(path), path); }

const std::vector<std::string>& psignifit_option_names() {
  static const std::vector<std::string> names = {
      "expType", "expN",    "sigmoidName", "threshPC", "widthalpha",     "betaPrior",   "estimateType",
      "fixedPars", "confP", "poolxTol",    "poolMaxGap", "poolMaxLength", "nblocks",    "stimulusRange",
      "stepN",   "mbStepN", "maxBorderValue", "moveBorders", "theta0"};
  return names;
}

PsignifitOptions parse_psignifit_options(const std::string& text, const std::string& file_name) {
  json document;
  try {
    document = json::parse(text);
  } catch (const json::parse_error& error) {
    // The byte offset the parser stopped at, as line and column.
    int line = 1, column = 1;
    for (std::size_t i = 0; i + 1 < error.byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    throw ConfigError({file_name, line, column}, "", std::string("not valid JSON: ") + error.what());
  }
  if (!document.is_object()) throw ConfigError({file_name, 1, 1}, "", "the options must be a JSON object {\"name\": value, ...}");
  const OptionReader reader(text, file_name);
  PsignifitOptions options;
  for (const auto& [key, value] : document.items()) read_option(options, reader, key, value);
  return options;
}

PsignifitOptions read_psignifit_options(const std::string& path) { return parse_psignifit_options(read_text(path), path); }

std::string psignifit_result_json(const PsignifitResult& result) {
  const auto parameters = [](const PsignifitParameters& values) { return json(std::vector<double>(values.begin(), values.end())); };
  json out;
  out["Fit"] = parameters(result.fit);
  out["MAP"] = parameters(result.map);
  out["meanFit"] = parameters(result.mean_fit);
  // psignifit's layout: per parameter [[lower bounds...], [upper bounds...]] over the credibilities.
  json intervals = json::array();
  for (int p = 0; p < kPsignifitParameters; ++p) {
    json lows = json::array(), highs = json::array();
    for (const PsignifitInterval& interval : result.intervals[p]) {
      lows.push_back(interval.low);
      highs.push_back(interval.high);
    }
    intervals.push_back(json::array({lows, highs}));
  }
  out["conf_Intervals"] = intervals;
  out["confP"] = result.options.credibility;
  out["deviance"] = result.deviance;
  out["devianceResiduals"] = result.deviance_residuals;
  out["logPmax"] = result.log_p_max;
  out["integral"] = result.integral;
  json data = json::array();
  for (const PsignifitBlock& block : result.blocks) data.push_back(json::array({block.level, block.correct, block.trials}));
  out["data"] = data;
  out["X1D"] = result.grid;
  out["marginals"] = result.marginals;
  out["marginalsX"] = result.grid;
  out["marginalsW"] = result.marginal_weights;
  // Read off the estimate: the stimulus level at threshPC of the sigmoid and psi's slope there,
  // in stimulus units (psignifit's getThreshold and getSlopePC).
  const double threshold = psignifit_threshold(result.options, result.fit, result.options.thresh_pc);
  out["thresholdLevel"] = threshold;
  out["slopeAtThreshold"] = psignifit_slope(result.options, result.fit, threshold);
  out["sigmoidName"] = psignifit_sigmoid_name(result.options.sigmoid);
  out["stimulusRangeFitted"] = result.fitted_range;
  if (result.options.generating_parameters) out["theta0"] = parameters(*result.options.generating_parameters);
  return out.dump(1) + "\n";
}

}  // namespace glarelab::analysis
