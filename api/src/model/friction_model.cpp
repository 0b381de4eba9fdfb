#include "hapticd/model/friction_model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>

namespace hapticd::model {

double FrictionModel::sliding(double velocity) const noexcept {
  const double v = std::min(std::abs(velocity), velocity_max);
  return (((p[4] * v + p[3]) * v + p[2]) * v + p[1]) * v + p[0];
}

double FrictionModel::magnitude(double velocity, double load_torque) const noexcept {
  const double l = std::abs(load_torque);
  return std::max(0.0, sliding(velocity) + (load[2] * l + load[1]) * l + load[0]);
}

namespace {

// Weighted least squares for the columns produced by `row`; nothing when rank-deficient.
// ridge: weight (relative to the summed sample weights) pulling the solution towards prior.
template <int N, class Row>
std::optional<Eigen::Matrix<double, N, 1>> weighted_fit(
    std::span<const FrictionSample> samples, Row row, double ridge = 0.0,
    const Eigen::Matrix<double, N, 1>& prior = Eigen::Matrix<double, N, 1>::Zero()) {
  Eigen::Matrix<double, N, N> ata = Eigen::Matrix<double, N, N>::Zero();
  Eigen::Matrix<double, N, 1> atb = Eigen::Matrix<double, N, 1>::Zero();
  double total = 0.0;
  for (const FrictionSample& s : samples) {
    const Eigen::Matrix<double, N, 1> r = row(s.speed);
    ata.noalias() += s.weight * r * r.transpose();
    atb.noalias() += s.weight * r * s.torque;
    total += s.weight;
  }
  if (ridge > 0.0) {
    ata.diagonal().array() += ridge * total;
    atb += ridge * total * prior;
  }
  const Eigen::ColPivHouseholderQR<Eigen::Matrix<double, N, N>> qr(ata);
  if (qr.rank() < N) return std::nullopt;
  return Eigen::Matrix<double, N, 1>(qr.solve(atb));
}

}  // namespace

std::optional<FrictionModel> fit_sliding_friction(std::span<const FrictionSample> samples, const FrictionModel& base,
                                                  double regularization) {
  std::set<double> speeds;
  double highest = 0.0;
  for (const FrictionSample& s : samples) {
    if (!(s.speed > 0.0) || !std::isfinite(s.torque) || !(s.weight > 0.0)) continue;
    speeds.insert(s.speed);
    highest = std::max(highest, s.speed);
  }
  if (speeds.size() < 6) return std::nullopt;
  // Scale the speeds to [0, 1] for a well-conditioned normal system.
  const double scale = highest;
  Eigen::Matrix<double, 5, 1> prior;
  double power = 1.0;
  for (int i = 0; i < 5; ++i) {
    prior[i] = base.p[static_cast<std::size_t>(i)] * power;
    power *= scale;
  }
  const auto x = weighted_fit<5>(
      samples,
      [scale](double v) {
        const double u = v / scale;
        return Eigen::Matrix<double, 5, 1>(1.0, u, u * u, u * u * u, u * u * u * u);
      },
      regularization, prior);
  if (!x) return std::nullopt;
  FrictionModel m = base;
  power = 1.0;
  for (int i = 0; i < 5; ++i) {
    m.p[static_cast<std::size_t>(i)] = (*x)[i] / power;
    power *= scale;
  }
  m.velocity_max = highest;
  return m;
}

std::optional<std::array<double, 3>> fit_load_friction(std::span<const FrictionSample> samples) {
  double highest = 0.0;
  for (const FrictionSample& s : samples) highest = std::max(highest, std::abs(s.speed));
  if (samples.size() < 3 || !(highest > 0.0)) return std::nullopt;
  const auto x = weighted_fit<3>(samples, [highest](double t) {
    const double u = std::abs(t) / highest;
    return Eigen::Matrix<double, 3, 1>(1.0, u, u * u);
  });
  if (!x) return std::nullopt;
  return std::array<double, 3>{(*x)[0], (*x)[1] / highest, (*x)[2] / (highest * highest)};
}

}  // namespace hapticd::model
