#pragma once
// The off-loop half of the adaptive sliding-friction compensation ([U06] methods 1, [4.24]):
// a worker thread receives the loop's binned friction estimates every T_update (lock-free hand-over), adds
// them to its memory (older data weighted down by `memory`), fits the 4th-order sliding-friction model per
// joint by least squares, checks the fit and hands accepted parameters back (lock-free). A rejected fit keeps
// the old parameters. Checks, per joint:
//   - excitation: at least min_bins velocity bins with min_bin_samples samples, spanning min_span rad/s;
//   - plausibility: a finite curve, positive over the fitted range, residual below 25 % of the mean friction;
//   - no over-compensation: at low speeds (< low_speed) the compensated share of the curve (fraction x model)
//     stays below the measured bin averages, and so does its value at rest (p0) against the lowest bin's
//     average (an over-compensating low-speed model makes a loosely held handle oscillate).
// The fit is pulled gently towards the present curve (ridge regularization): over the narrow speed range of
// normal use a free 4th-order fit is poorly determined.
// Every attempt is written to an optional CSV log (time, joint, accepted, reason, parameters).
#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "friction_compensation.hpp"
#include "friction_estimator.hpp"
#include "hapticd/realtime/latest_value.hpp"

namespace hapticd::controllers {

struct RetuneChecks {
  int min_bins = 6;
  double min_bin_samples = 100.0;
  double min_span = 0.4;         // [rad/s]
  double low_speed = 1.0;        // [rad/s]
  double fraction = 0.8;         // share of the model the compensator applies
  double regularization = 0.01;  // ridge weight towards the present curve
  double memory = 0.5;           // weight of the previous data at each update
};

// Outcome of one joint's fit.
struct RetuneResult {
  bool accepted = false;
  std::string reason;  // why it was rejected; empty when accepted
  model::FrictionModel model;
  int bins = 0;
};

// Fits and checks one joint from its bins (pure: unit-testable).
RetuneResult retune_joint(const FrictionBinData& bins, int joint, const model::FrictionModel& current,
                          const RetuneChecks& checks);

struct RetunedModels {
  FrictionModels models{};
  std::uint64_t sequence = 0;  // the sequence of the bin data they were fitted to
};

class FrictionRetuner {
 public:
  FrictionRetuner() = default;
  FrictionRetuner(const FrictionRetuner&) = delete;
  FrictionRetuner& operator=(const FrictionRetuner&) = delete;
  ~FrictionRetuner() { stop(); }

  // Not real-time safe: starts the worker. log_file empty: no log.
  void start(int dof, const FrictionModels& initial, const RetuneChecks& checks, const std::filesystem::path& log_file);
  void stop();

  // Loop side (real-time safe): hands over a copy of the bins; takes fitted models if any arrived.
  void submit(const FrictionBinData& bins) noexcept { bins_.publish(bins); }
  bool take(RetunedModels& out) noexcept { return results_.take(out); }
  // Worker statistics (any thread).
  [[nodiscard]] std::uint64_t fits_accepted() const noexcept { return accepted_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t fits_rejected() const noexcept { return rejected_.load(std::memory_order_relaxed); }

 private:
  void run();
  void process(const FrictionBinData& fresh);

  int dof_ = 0;
  RetuneChecks checks_;
  FrictionModels models_{};
  FrictionBinData memory_{};
  bool has_memory_ = false;
  std::ofstream log_;
  realtime::LatestValue<FrictionBinData> bins_;
  realtime::LatestValue<RetunedModels> results_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> accepted_{0}, rejected_{0};
  std::thread worker_;
};

}  // namespace hapticd::controllers
