// The assessment colours of §4.2 (see the header).
#include "stripweave/layout/assessment.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

namespace {

// Valence and curvature that agree exactly (a flat region with v = 4, K = 0)
// must not be flagged because of rounding in K.
constexpr double kRounding = 1e-9;

}  // namespace

double ideal_valence(double total_curvature) { return 4.0 - 2.0 * total_curvature / M_PI; }

int excess_extrema(const std::vector<int>& quarter_indices) {
  int positive = 0, negative = 0;
  for (int q : quarter_indices) positive += q > 0, negative += q < 0;
  return std::max(0, positive - 1) + std::max(0, negative - 1);
}

RegionColour assess_region(bool disc, bool crease_problem, int excess, int valence, double total_curvature) {
  if (!disc) return RegionColour::Red;
  if (crease_problem) return RegionColour::Crease;
  if (excess > 0) return RegionColour::Orange;
  if (std::abs(valence - ideal_valence(total_curvature)) > 1 + kRounding) return RegionColour::Yellow;
  return RegionColour::None;
}

const char* colour_name(RegionColour colour) {
  switch (colour) {
    case RegionColour::Red: return "red";
    case RegionColour::Orange: return "orange";
    case RegionColour::Yellow: return "yellow";
    case RegionColour::Crease: return "crease";
    default: return "none";
  }
}

}  // namespace stripweave
