#pragma once
// A session served: its devices on the executor's loop, with the DDS interface (when the session file has a dds
// section), the live view (a live_view section), the monitor and, when asked, a recording. The one place these are
// assembled: `hapticd` runs a session file through it, and so do the end-to-end tests over DDS.
//
// Construction sets everything up before any device is powered (a recording that cannot be opened or a DDS
// interface or live view that cannot start throws std::runtime_error, and nothing moved); run() powers the devices,
// runs the loop until its duration ends or `stop` is set, and leaves every device disabled.
#include <atomic>
#include <filesystem>
#include <memory>
#include <vector>

#include "app/session_monitor.hpp"
#include "config/session_config.hpp"
#include "cycle/loop_plan.hpp"
#include "doors/doors.hpp"
#include "executor/executor.hpp"
#include "live_view/live_view.hpp"
#include "recorder/recorder.hpp"
#include "session/device_session.hpp"

namespace hapticd::server {

struct ServeOptions {
  std::filesystem::path record_file;  // the HDF5 recording (docs/recording.md); empty: no recording
  // false: no SCHED_FIFO, locked memory or CPU pinning for the loop and the DDS threads, whatever the session
  // file says (tests on a shared machine).
  bool realtime_setup = true;
  // Set by whoever ends the session (a signal handler, a test); the monitor logs the request once.
  const std::atomic<bool>* stop = nullptr;
};

// What a recording says of the session before its first cycle: the session file, the devices and their schemes.
RecordingHeader recording_header(const SessionConfig& config, const std::vector<DeviceSession*>& devices);

class ServedSession {
 public:
  // stages: the device groups' stages (session_builder's build_group_stages); they outlive this.
  ServedSession(const SessionConfig& config, const std::vector<DeviceSession*>& devices,
                std::vector<GroupStage*> stages, const ServeOptions& options);
  ~ServedSession();  // stops the DDS interface
  ServedSession(const ServedSession&) = delete;
  ServedSession& operator=(const ServedSession&) = delete;

  // Runs the loop (Executor::run, the monitor polling beside it); then the recording is finished and the DDS
  // interface stopped. Throws what the executor throws (every device is disabled by then).
  ExecutorResult run(const std::atomic<bool>& stop);

  // The listener the loop calls after every cycle: the DDS interface's, or none. A listener put in its place
  // must hand each call on to the one it replaces.
  [[nodiscard]] CycleListener* cycle_listener() const noexcept { return listener_; }
  void set_cycle_listener(CycleListener* listener);

  // The gate and its doors (null without a dds or engine_socket section).
  [[nodiscard]] Doors* doors() const noexcept { return doors_.get(); }
  [[nodiscard]] const SessionMonitor& monitor() const noexcept { return *monitor_; }
  [[nodiscard]] Recorder* recorder() const noexcept { return recorder_.get(); }               // null: not recording
  [[nodiscard]] live_view::LiveView* live_view() const noexcept { return live_view_.get(); }  // null: none
  // Where the threads run: the loop's CPU (-1 not pinned) and the DDS threads' CPUs (empty: not pinned).
  [[nodiscard]] int loop_cpu() const noexcept { return settings_.cpu; }
  [[nodiscard]] const std::vector<int>& dds_cpus() const noexcept { return dds_cpus_; }

 private:
  ExecutorSettings settings_;
  std::vector<int> dds_cpus_;
  std::unique_ptr<Recorder> recorder_;
  std::unique_ptr<LoopPlan> loops_;  // which loop drives which device
  std::unique_ptr<Executor> executor_;
  std::unique_ptr<live_view::LiveView> live_view_;
  std::unique_ptr<Doors> doors_;  // after the live view: destroyed first (it hands the live view the worlds)
  std::unique_ptr<SessionMonitor> monitor_;
  CycleListener* listener_ = nullptr;
};

}  // namespace hapticd::server
