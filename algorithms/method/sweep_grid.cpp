#include "algorithms/method/sweep_grid.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace fogpipe::method {
namespace {

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, separator)) parts.push_back(part);
  return parts;
}

template <typename T>
bool ParseNumber(const std::string& text, T* value) {
  try {
    std::size_t used = 0;
    if constexpr (std::is_same_v<T, int>) {
      *value = std::stoi(text, &used);
    } else {
      *value = std::stod(text, &used);
    }
    return used == text.size() && !text.empty();
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

bool SweepGrid::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (ar_orders.empty() || q_scales.empty() || r_scales.empty()) {
    return fail("every grid axis needs at least one value");
  }
  for (int p : ar_orders) {
    if (p < 1 || p > 200) return fail("AR orders must be in 1..200");
  }
  for (const auto* scales : {&q_scales, &r_scales}) {
    for (double s : *scales) {
      if (!(s > 0.0) || !std::isfinite(s)) return fail("q and R scales must be finite and > 0");
    }
  }
  return true;
}

int SweepGrid::max_order() const {
  return ar_orders.empty() ? 0 : *std::max_element(ar_orders.begin(), ar_orders.end());
}

std::vector<SweepSetting> GridSettings(const SweepGrid& grid) {
  std::vector<SweepSetting> settings;
  for (int p : grid.ar_orders) {
    settings.push_back({p, 1.0, 1.0, true});
    for (double q : grid.q_scales) {
      for (double r : grid.r_scales) settings.push_back({p, q, r, false});
    }
  }
  return settings;
}

bool ParseIntList(const std::string& text, std::vector<int>* values, std::string* error) {
  values->clear();
  const auto range = Split(text, ':');
  if (range.size() == 2 || range.size() == 3) {
    int from = 0, to = 0, step = 1;
    if (!ParseNumber(range[0], &from) || !ParseNumber(range[1], &to) ||
        (range.size() == 3 && !ParseNumber(range[2], &step)) || step < 1 || to < from) {
      *error = "'" + text + "': expected FROM:TO[:STEP] with FROM <= TO and STEP >= 1";
      return false;
    }
    for (int v = from; v <= to; v += step) values->push_back(v);
    return true;
  }
  for (const std::string& part : Split(text, ',')) {
    int v = 0;
    if (!ParseNumber(part, &v)) {
      *error = "'" + text + "': expected integers separated by ',' or FROM:TO[:STEP]";
      return false;
    }
    values->push_back(v);
  }
  return !values->empty();
}

bool ParseScaleList(const std::string& text, std::vector<double>* values, std::string* error) {
  values->clear();
  const auto range = Split(text, ':');
  if (range.size() == 3) {
    double from = 0, to = 0;
    int count = 0;
    if (!ParseNumber(range[0], &from) || !ParseNumber(range[1], &to) ||
        !ParseNumber(range[2], &count) || !(from > 0) || !(to >= from) || count < 1) {
      *error = "'" + text + "': expected FROM:TO:COUNT with 0 < FROM <= TO and COUNT >= 1";
      return false;
    }
    for (int i = 0; i < count; ++i) {
      const double t = count == 1 ? 0.0 : static_cast<double>(i) / (count - 1);
      values->push_back(from * std::pow(to / from, t));
    }
    return true;
  }
  for (const std::string& part : Split(text, ',')) {
    double v = 0;
    if (!ParseNumber(part, &v)) {
      *error = "'" + text + "': expected numbers separated by ',' or FROM:TO:COUNT";
      return false;
    }
    values->push_back(v);
  }
  return !values->empty();
}

}  // namespace fogpipe::method
