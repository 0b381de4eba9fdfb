#pragma once
// Builds the ViSHaRD10 SCARA look-up table by numerical optimisation ([U06] methods 3, [3.46-3.48];
// docs/redundancy.md): the unknowns are the elbow codes (s, t) in [-1, 1]^2 of every mesh point; the objective
// is the largest joint difference between neighbouring mesh points per tip distance, each joint normalised by its
// speed limit (so its inverse is the tip speed the joints allow), reached from the 2-norm by continuation
// through p-norms. The initial guess: 16 radial lines solved separately, each by multistart, interpolated over
// the angle. NLopt (L-BFGS with bounds) does the optimising.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "scara_table.hpp"

namespace hapticd::tools {

struct ScaraWorkspace {
  double radius_min = 0.15, radius_max = 0.8;
  double excluded_sector_deg = 30.0;          // width of the sector left out
  double excluded_sector_centre_deg = 180.0;  // where (the base line: behind the base)
  int radii = 12, angles = 48;
};

struct ScaraOptimiserSettings {
  std::vector<double> norms = {2, 4, 8, 16, 32, 64};  // the continuation towards the infinity norm
  int evaluations_per_norm = 400;
  int radial_lines = 16;
  int starts_per_line = 8;
  std::uint64_t seed = 1;
  int branch12 = 1, branch34 = 1;
  // Optional: a table of a smaller workspace whose codes (continued outwards beyond its border) replace the radial
  // lines' initial guess (growing the workspace step by step: the smaller one's optimum is a good start).
  const ik::vishard10::ScaraTable* warm_start = nullptr;
};

struct ScaraOptimiserResult {
  ik::vishard10::ScaraTable table;
  double initial_worst_rate = 0.0;               // of the radial-line initial guess [rad/s per m/s, normalised]
  double prismatic_pairs_worst_rate = 0.0;       // of the two-prismatic-pairs inverse function on the same mesh
  std::array<double, 4> worst_rate_per_joint{};  // rad/s per m/s
  std::string log;
};

// The worst normalised joint rate per tip speed of a table (1 / the tip speed the limits allow), and per joint.
double worst_normalised_rate(const ik::vishard10::Geometry& g, const ik::vishard10::ScaraTable& table,
                             const std::array<double, 4>& speed_limits, std::array<double, 4>* per_joint = nullptr);

ScaraOptimiserResult optimise_scara_table(const ik::vishard10::Geometry& g, const std::array<double, 4>& speed_limits,
                                          const ScaraWorkspace& workspace, const ScaraOptimiserSettings& settings);

}  // namespace hapticd::tools
