#include "friction_retuner.hpp"

#include <chrono>
#include <cmath>
#include <iomanip>

namespace hapticd::controllers {

RetuneResult retune_joint(const FrictionBinData& bins, int joint, const model::FrictionModel& current,
                          const RetuneChecks& checks) {
  RetuneResult r;
  r.model = current;
  const auto j = static_cast<std::size_t>(joint);
  std::vector<model::FrictionSample> samples;
  double lowest = 1e9, highest = 0.0;
  for (std::size_t b = 0; b < static_cast<std::size_t>(kFrictionBins); ++b) {
    const double n = bins.count[j][b];
    if (n < checks.min_bin_samples) continue;
    const double speed = bins.speed_sum[j][b] / n;
    samples.push_back({speed, bins.sum[j][b] / n, n});
    lowest = std::min(lowest, speed);
    highest = std::max(highest, speed);
  }
  r.bins = static_cast<int>(samples.size());
  if (r.bins < checks.min_bins || highest - lowest < checks.min_span) {
    r.reason = "poor excitation (" + std::to_string(r.bins) + " bins over " +
               std::to_string(std::max(0.0, highest - lowest)) + " rad/s)";
    return r;
  }
  // Equal weight per bin: the bins the device dwells in must not dominate the curve.
  for (auto& s : samples) s.weight = 1.0;
  const auto fit = model::fit_sliding_friction(samples, current, checks.regularization);
  if (!fit) {
    r.reason = "rank-deficient fit";
    return r;
  }
  const model::FrictionModel& m = *fit;
  double residual = 0.0, mean = 0.0;
  for (const auto& s : samples) {
    residual += std::pow(m.sliding(s.speed) - s.torque, 2);
    mean += std::abs(s.torque);
  }
  residual = std::sqrt(residual / static_cast<double>(samples.size()));
  mean /= static_cast<double>(samples.size());
  for (int k = 0; k <= 50; ++k) {
    const double v = m.velocity_max * k / 50.0;
    const double f = m.sliding(v);
    if (!std::isfinite(f) || f <= 0.0) {
      r.reason = "implausible curve (not positive at " + std::to_string(v) + " rad/s)";
      return r;
    }
  }
  if (residual > 0.25 * mean) {
    r.reason = "implausible fit (residual " + std::to_string(residual) + " N m)";
    return r;
  }
  for (const auto& s : samples) {
    if (s.speed < checks.low_speed && checks.fraction * m.sliding(s.speed) > s.torque) {
      r.reason = "over-compensation at " + std::to_string(s.speed) + " rad/s";
      return r;
    }
  }
  if (checks.fraction * m.p[0] > samples.front().torque) {
    r.reason = "over-compensation at rest (p0 above the lowest bin)";
    return r;
  }
  r.model = m;
  r.accepted = true;
  return r;
}

void FrictionRetuner::start(int dof, const FrictionModels& initial, const RetuneChecks& checks,
                            const std::filesystem::path& log_file) {
  stop();
  dof_ = dof;
  models_ = initial;
  checks_ = checks;
  has_memory_ = false;
  if (!log_file.empty()) {
    log_.open(log_file);
    if (!log_) throw std::runtime_error("cannot write the adaptive friction log " + log_file.string());
    log_ << "time_s,joint,accepted,bins,p0,p1,p2,p3,p4,velocity_max,reason\n";
  }
  stop_.store(false);
  worker_ = std::thread([this] { run(); });
}

void FrictionRetuner::stop() {
  stop_.store(true);
  if (worker_.joinable()) worker_.join();
  if (log_.is_open()) log_.close();
}

void FrictionRetuner::run() {
  FrictionBinData fresh;
  while (!stop_.load(std::memory_order_relaxed)) {
    if (bins_.take(fresh)) {
      process(fresh);
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }
}

void FrictionRetuner::process(const FrictionBinData& fresh) {
  if (!has_memory_) {
    memory_ = fresh;
    has_memory_ = true;
  } else {
    for (int j = 0; j < dof_; ++j) {
      const auto k = static_cast<std::size_t>(j);
      for (std::size_t b = 0; b < static_cast<std::size_t>(kFrictionBins); ++b) {
        memory_.sum[k][b] = checks_.memory * memory_.sum[k][b] + fresh.sum[k][b];
        memory_.speed_sum[k][b] = checks_.memory * memory_.speed_sum[k][b] + fresh.speed_sum[k][b];
        memory_.count[k][b] = checks_.memory * memory_.count[k][b] + fresh.count[k][b];
      }
    }
    memory_.time_s = fresh.time_s;
    memory_.sequence = fresh.sequence;
  }
  for (int j = 0; j < dof_; ++j) {
    const RetuneResult r = retune_joint(memory_, j, models_[static_cast<std::size_t>(j)], checks_);
    if (r.accepted) {
      models_[static_cast<std::size_t>(j)] = r.model;
      accepted_.fetch_add(1, std::memory_order_relaxed);
    } else {
      rejected_.fetch_add(1, std::memory_order_relaxed);
    }
    if (log_.is_open()) {
      const auto& p = r.model.p;
      log_ << std::setprecision(6) << fresh.time_s << ',' << j << ',' << (r.accepted ? 1 : 0) << ',' << r.bins << ','
           << p[0] << ',' << p[1] << ',' << p[2] << ',' << p[3] << ',' << p[4] << ',' << r.model.velocity_max << ",\""
           << r.reason << "\"\n";
    }
  }
  if (log_.is_open()) log_.flush();
  results_.publish(RetunedModels{models_, fresh.sequence});
}

}  // namespace hapticd::controllers
