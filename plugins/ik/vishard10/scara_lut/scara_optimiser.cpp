#include "scara_optimiser.hpp"

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

namespace hapticd::tools {
namespace {

using ik::vishard10::Geometry;
using ik::vishard10::ScaraTable;
constexpr double kPi = std::numbers::pi;

struct Edge {
  int a = 0, b = 0;
  double length = 0.0;
};

// One optimisation problem: mesh points, their edges, and the codes as unknowns.
struct Problem {
  const Geometry* g = nullptr;
  std::array<double, 4> limits{};
  int branch12 = 1, branch34 = 1;
  std::vector<Eigen::Vector2d> points;  // tip positions relative to the base
  std::vector<Edge> edges;
  double p = 2.0;
  // scratch
  std::vector<std::array<double, 4>> q, dq_ds, dq_dt;
  int evaluations = 0;

  bool joints(int k, double s, double t, std::array<double, 4>& out) const {
    Eigen::Vector2d elbow;
    if (!ik::vishard10::elbow_from_code(*g, points[static_cast<std::size_t>(k)], s, t, elbow)) return false;
    return ik::vishard10::scara_joints_from_elbow(*g, points[static_cast<std::size_t>(k)], elbow, branch12, branch34,
                                                  out.data());
  }

  // Normalised rate of joint j on edge e (and the signed difference).
  double rate(const Edge& e, int j, double& difference) const {
    difference = std::remainder(q[static_cast<std::size_t>(e.b)][static_cast<std::size_t>(j)] -
                                    q[static_cast<std::size_t>(e.a)][static_cast<std::size_t>(j)],
                                2.0 * kPi);
    return std::abs(difference) / (e.length * limits[static_cast<std::size_t>(j)]);
  }

  // The joints of every mesh point for the codes x = (s0, t0, s1, t1, ...), with their derivatives by the codes
  // when `derivatives`; false if a code leaves a pair out of reach.
  bool all_joints(const double* x, bool derivatives) {
    const auto n = points.size();
    q.resize(n);
    dq_ds.resize(n);
    dq_dt.resize(n);
    constexpr double kStep = 1e-6;
    for (std::size_t k = 0; k < n; ++k) {
      const double s = x[2 * k], t = x[2 * k + 1];
      if (!joints(static_cast<int>(k), s, t, q[k])) return false;
      if (derivatives) {
        std::array<double, 4> probe{};
        const double hs = s > 0 ? -kStep : kStep, ht = t > 0 ? -kStep : kStep;  // step inwards
        (void)joints(static_cast<int>(k), s + hs, t, probe);
        for (int j = 0; j < 4; ++j)
          dq_ds[k][static_cast<std::size_t>(j)] =
              std::remainder(probe[static_cast<std::size_t>(j)] - q[k][static_cast<std::size_t>(j)], 2 * kPi) / hs;
        (void)joints(static_cast<int>(k), s, t + ht, probe);
        for (int j = 0; j < 4; ++j)
          dq_dt[k][static_cast<std::size_t>(j)] =
              std::remainder(probe[static_cast<std::size_t>(j)] - q[k][static_cast<std::size_t>(j)], 2 * kPi) / ht;
      }
    }
    return true;
  }

  // The largest normalised rate over the edges, for the joints all_joints left in q.
  double largest_of_joints() const {
    double largest = 0.0, difference = 0.0;
    for (const Edge& e : edges)
      for (int j = 0; j < 4; ++j) largest = std::max(largest, rate(e, j, difference));
    return largest;
  }

  // The p-norm of all normalised rates and its gradient over the codes.
  double evaluate(const double* x, double* gradient) {
    ++evaluations;
    const auto n = points.size();
    if (!all_joints(x, gradient != nullptr)) {
      if (gradient != nullptr) std::fill(gradient, gradient + 2 * n, 0.0);
      return 1e9;  // cannot happen inside [-1, 1]^2 for a reachable tip; a wall if it does
    }
    double difference = 0.0;
    const double largest = largest_of_joints();
    if (largest == 0.0) return 0.0;
    double sum = 0.0;
    for (const Edge& e : edges)
      for (int j = 0; j < 4; ++j) sum += std::pow(rate(e, j, difference) / largest, p);
    const double f = largest * std::pow(sum, 1.0 / p);
    if (gradient != nullptr) {
      std::fill(gradient, gradient + 2 * n, 0.0);
      for (const Edge& e : edges) {
        for (int j = 0; j < 4; ++j) {
          const double r = rate(e, j, difference);
          if (r == 0.0) continue;
          // dF/dr = (r / F)^(p-1); dr/dq_b = sign / (L v), dr/dq_a = -sign / (L v).
          const double w = std::pow(r / f, p - 1.0) * (difference > 0 ? 1.0 : -1.0) /
                           (e.length * limits[static_cast<std::size_t>(j)]);
          const auto a = static_cast<std::size_t>(e.a), b = static_cast<std::size_t>(e.b);
          gradient[2 * b] += w * dq_ds[b][static_cast<std::size_t>(j)];
          gradient[2 * b + 1] += w * dq_dt[b][static_cast<std::size_t>(j)];
          gradient[2 * a] -= w * dq_ds[a][static_cast<std::size_t>(j)];
          gradient[2 * a + 1] -= w * dq_dt[a][static_cast<std::size_t>(j)];
        }
      }
    }
    return f;
  }

  double largest_rate(const double* x) { return all_joints(x, false) ? largest_of_joints() : 1e9; }
};

Problem empty_problem(const Geometry& g, const std::array<double, 4>& limits, int branch12, int branch34) {
  Problem p;
  p.g = &g;
  p.limits = limits;
  p.branch12 = branch12;
  p.branch34 = branch34;
  return p;
}

double objective(unsigned n, const double* x, double* gradient, void* data) {
  (void)n;
  return static_cast<Problem*>(data)->evaluate(x, gradient);
}

// Minimises over the codes by continuation through the p-norms; returns the final largest rate.
double minimise(Problem& problem, std::vector<double>& x, const ScaraOptimiserSettings& settings) {
  nlopt_opt opt = nlopt_create(NLOPT_LD_LBFGS, static_cast<unsigned>(x.size()));
  nlopt_set_lower_bounds1(opt, -0.999);
  nlopt_set_upper_bounds1(opt, 0.999);
  nlopt_set_min_objective(opt, objective, &problem);
  nlopt_set_maxeval(opt, settings.evaluations_per_norm);
  nlopt_set_xtol_rel(opt, 1e-8);
  // The continuation follows every step (a 2-norm optimum may have a larger maximum than the start: the higher
  // norms then pull it down); the best maximum seen on the way is kept.
  std::vector<double> best = x;
  double best_largest = problem.largest_rate(x.data());
  for (double p : settings.norms) {
    problem.p = p;
    double value = 0.0;
    const nlopt_result r = nlopt_optimize(opt, x.data(), &value);
    (void)r;  // a stop at the evaluation limit or by round-off still leaves a usable point
    const double largest = problem.largest_rate(x.data());
    if (largest < best_largest) {
      best_largest = largest;
      best = x;
    }
  }
  x = best;
  nlopt_destroy(opt);
  return best_largest;
}

void add_grid_edges(Problem& problem, int radii, int angles) {
  const auto index = [angles](int ir, int ia) { return ir * angles + ia; };
  for (int ir = 0; ir < radii; ++ir) {
    for (int ia = 0; ia < angles; ++ia) {
      if (ir + 1 < radii) problem.edges.push_back({index(ir, ia), index(ir + 1, ia), 0.0});
      if (ia + 1 < angles) problem.edges.push_back({index(ir, ia), index(ir, ia + 1), 0.0});
    }
  }
  for (Edge& e : problem.edges)
    e.length = (problem.points[static_cast<std::size_t>(e.b)] - problem.points[static_cast<std::size_t>(e.a)]).norm();
}

// The code of the two-prismatic-pairs inverse function (pair 1-2 along x, pair 3-4 along y) for a tip position,
// found by inverting elbow_from_code for its elbow point.
Eigen::Vector2d prismatic_pairs_code(const Geometry& g, const Eigen::Vector2d& tip) {
  const Eigen::Vector2d elbow = g.base + Eigen::Vector2d(tip.x(), 0.0);  // pair 1-2 moves the elbow along x
  const double r1 = g.scara_link[0] + g.scara_link[1], r2 = g.scara_link[2] + g.scara_link[3];
  const double d = tip.norm();
  const Eigen::Vector2d along = tip / d, across(-along.y(), along.x());
  const Eigen::Vector2d e = elbow - g.base;
  const double a = (d * d + r1 * r1 - r2 * r2) / (2.0 * d), h = std::sqrt(std::max(1e-12, r1 * r1 - a * a));
  const double y = e.dot(across), x = e.dot(along);
  const double far = std::sqrt(std::max(0.0, r1 * r1 - y * y)), near = d - std::sqrt(std::max(0.0, r2 * r2 - y * y));
  return Eigen::Vector2d(std::clamp(y / h, -0.999, 0.999),
                         std::clamp((x - 0.5 * (far + near)) / std::max(1e-12, 0.5 * (far - near)), -0.999, 0.999));
}

}  // namespace

double worst_normalised_rate(const Geometry& g, const ScaraTable& table, const std::array<double, 4>& speed_limits,
                             std::array<double, 4>* per_joint) {
  Problem problem = empty_problem(g, speed_limits, table.branch12, table.branch34);
  for (int ir = 0; ir < table.radius_count; ++ir)
    for (int ia = 0; ia < table.angle_count; ++ia) problem.points.push_back(table.point(ir, ia));
  add_grid_edges(problem, table.radius_count, table.angle_count);
  std::vector<double> x;
  for (const auto& c : table.code) {
    x.push_back(c.x());
    x.push_back(c.y());
  }
  const double worst = problem.largest_rate(x.data());
  if (per_joint != nullptr) {
    per_joint->fill(0.0);
    double difference = 0.0;
    for (const Edge& e : problem.edges)
      for (int j = 0; j < 4; ++j)
        (*per_joint)[static_cast<std::size_t>(j)] =
            std::max((*per_joint)[static_cast<std::size_t>(j)],
                     problem.rate(e, j, difference) * speed_limits[static_cast<std::size_t>(j)]);
  }
  return worst;
}

ScaraOptimiserResult optimise_scara_table(const Geometry& g, const std::array<double, 4>& speed_limits,
                                          const ScaraWorkspace& w, const ScaraOptimiserSettings& settings) {
  ScaraOptimiserResult result;
  ScaraTable& table = result.table;
  const double centre = w.excluded_sector_centre_deg * kPi / 180.0, half = 0.5 * w.excluded_sector_deg * kPi / 180.0;
  table.radius_min = w.radius_min;
  table.radius_max = w.radius_max;
  table.radius_count = w.radii;
  table.angle_min = std::remainder(centre + half, 2.0 * kPi);
  table.angle_max = table.angle_min + 2.0 * kPi - 2.0 * half;
  table.angle_count = w.angles;
  table.branch12 = settings.branch12;
  table.branch34 = settings.branch34;
  std::ostringstream log;
  std::mt19937_64 rng(settings.seed);
  std::uniform_real_distribution<double> uniform(-0.9, 0.9);

  // 1. Radial lines, each by multistart.
  std::vector<std::vector<double>> lines;
  for (int l = 0; l < settings.radial_lines; ++l) {
    const double angle = table.angle_min + (table.angle_max - table.angle_min) * l / (settings.radial_lines - 1);
    Problem line = empty_problem(g, speed_limits, settings.branch12, settings.branch34);
    for (int ir = 0; ir < w.radii; ++ir) {
      const double r = w.radius_min + (w.radius_max - w.radius_min) * ir / (w.radii - 1);
      line.points.push_back(r * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    }
    add_grid_edges(line, w.radii, 1);
    std::vector<double> best;
    double best_value = 1e18, best_distance = 1e18;
    for (int start = 0; start < settings.starts_per_line; ++start) {
      std::vector<double> x(2 * static_cast<std::size_t>(w.radii));
      const double s0 = uniform(rng), t0 = uniform(rng);
      for (int i = 0; i < w.radii; ++i) {
        x[2 * static_cast<std::size_t>(i)] = s0;
        x[2 * static_cast<std::size_t>(i) + 1] = t0;
      }
      const double value = minimise(line, x, settings);
      // Among equally good starts take the one closest to the previous line (no flip between mirror optima).
      double distance = 0.0;
      if (!lines.empty())
        for (std::size_t i = 0; i < x.size(); ++i) distance += std::abs(x[i] - lines.back()[i]);
      const bool better = value < best_value * (1.0 - 1e-3);
      const bool as_good_and_closer = value <= best_value * (1.0 + 1e-3) && distance < best_distance;
      if (better || as_good_and_closer) {
        best_value = std::min(best_value, value);
        best_distance = distance;
        best = x;
      }
    }
    log << "radial line " << l << " at " << angle * 180.0 / kPi << " deg: worst normalised rate " << best_value << "\n";
    lines.push_back(best);
  }

  // 2. The initial guess: the lines interpolated over the angle.
  Problem full = empty_problem(g, speed_limits, settings.branch12, settings.branch34);
  std::vector<double> x;
  for (int ir = 0; ir < w.radii; ++ir) {
    for (int ia = 0; ia < w.angles; ++ia) {
      const Eigen::Vector2d p = table.point(ir, ia);
      full.points.push_back(p);
      const double f = static_cast<double>(ia) / (w.angles - 1) * (settings.radial_lines - 1);
      const int l = std::min(static_cast<int>(f), settings.radial_lines - 2);
      const double u = f - l;
      for (int c = 0; c < 2; ++c)
        x.push_back(
            (1 - u) *
                lines[static_cast<std::size_t>(l)][2 * static_cast<std::size_t>(ir) + static_cast<std::size_t>(c)] +
            u * lines[static_cast<std::size_t>(l) + 1][2 * static_cast<std::size_t>(ir) + static_cast<std::size_t>(c)]);
    }
  }
  add_grid_edges(full, w.radii, w.angles);
  if (settings.warm_start != nullptr) {
    // Beyond its mesh the smaller table's border codes continue outwards (a continuous guess).
    std::size_t inside = 0;
    for (std::size_t k = 0; k < full.points.size(); ++k) {
      Eigen::Vector2d code, clamped;
      if (settings.warm_start->code_at(full.points[k], code, clamped)) ++inside;
      x[2 * k] = std::clamp(code.x(), -0.999, 0.999);
      x[2 * k + 1] = std::clamp(code.y(), -0.999, 0.999);
    }
    log << "warm start: " << inside << " of " << full.points.size() << " mesh points inside the smaller workspace\n";
  }
  result.initial_worst_rate = full.largest_rate(x.data());

  // The two-prismatic-pairs inverse function on the same mesh, for comparison (where it reaches).
  {
    std::vector<double> y;
    for (const auto& p : full.points) {
      const Eigen::Vector2d c = prismatic_pairs_code(g, p);
      y.push_back(c.x());
      y.push_back(c.y());
    }
    result.prismatic_pairs_worst_rate = full.largest_rate(y.data());
  }

  // 3. The whole mesh.
  const double worst = minimise(full, x, settings);
  table.code.clear();
  for (std::size_t k = 0; k < full.points.size(); ++k) table.code.emplace_back(x[2 * k], x[2 * k + 1]);
  table.worst_rate = worst_normalised_rate(g, table, speed_limits, &result.worst_rate_per_joint);
  table.tip_speed = 1.0 / table.worst_rate;
  log << "initial guess: worst normalised rate " << result.initial_worst_rate << "; optimised " << worst << " after "
      << full.evaluations << " evaluations\n";
  result.log = log.str();
  return result;
}

}  // namespace hapticd::tools
