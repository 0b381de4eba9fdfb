#pragma once
// The end-to-end rig over DDS: a server (a session served as `hapticd` serves it, in this process, its own DDS
// participant) and the scene engine of examples/engines on the client library (a participant of its own), on a
// test domain of their own with the loopback-only configuration. Lockstep runs wait for the engine's answer to
// every state (dds.lockstep_sync), so they are repeatable; a recording listener on the loop thread captures what
// the device renders in every cycle.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "../../examples/engines/scene.hpp"
#include "app/served_session.hpp"
#include "hapticd/client/client.hpp"
#include "support/test_session.hpp"

namespace hapticd::server::e2e {

using client::Client;

// Records, on the loop thread, the environment force the device renders and the handle position each cycle.
class RecordingListener final : public CycleListener {
 public:
  RecordingListener(CycleListener* next, DeviceSession* device) : next_(next), device_(device) {
    force_.reserve(20000);
    position_.reserve(20000);
    weight_.reserve(20000);
    index_.reserve(20000);
  }
  void after_cycle(std::uint64_t index, bool lockstep) noexcept override {
    index_.push_back(index);
    force_.push_back(device_->task().wrench.force);
    position_.push_back(device_->chain_state().handle_pose.position);
    weight_.push_back(device_->engine_weight());
    next_->after_cycle(index, lockstep);
  }
  const std::vector<Eigen::Vector3d>& force() const { return force_; }
  const std::vector<Eigen::Vector3d>& position() const { return position_; }
  const std::vector<double>& engine_weight() const { return weight_; }
  // The loop's period index of each recorded cycle (a real-time loop that fell behind skips periods).
  const std::vector<std::uint64_t>& index() const { return index_; }

 private:
  CycleListener* next_;
  DeviceSession* device_;
  std::vector<Eigen::Vector3d> force_, position_;
  std::vector<double> weight_;
  std::vector<std::uint64_t> index_;
};

// Under a sanitizer the real-time loop runs several times slower than its period: the overrun watchdog (a
// device fault after 10 consecutive overruns) is off there, these runs look for races, not for timing.
#if defined(__SANITIZE_THREAD__) || defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

// The loop watchdogs of the real-time tests here, which test the DDS path, not the machine: loosened as in
// tests/e2e/session_copy.sh (why: there) - a shared CI machine runs the loop late now and then, for over 0.1 s
// in bursts. Under a sanitizer the loop runs several times slower than its period: the watchdogs are off there.
inline const std::string kRealtimeWatchdogs =
    kSanitized ? "max_consecutive_overruns: 0, max_stall_s: 0" : "max_consecutive_overruns: 2000, max_stall_s: 1.0";

// The chain of the rig's ViSHaRD3: admittance display (3 kg, 30 N s/m) with the virtual coupling (3000 N/m,
// 40 N s/m) for an engine's proxy, resolved acceleration control.
inline std::string coupling_chain_yaml() {
  return R"(    virtual_model:
      plugin: admittance
      parameters: {mass_kg: [3.0, 3.0, 3.0], damping_n_s_per_m: [30.0, 30.0, 30.0], rotation: false,
                   coupling: true, coupling_stiffness_n_per_m: 3000, coupling_damping_n_s_per_m: 40}
    controller:
      plugin: resolved_acceleration
      parameters: {task: translation}
)";
}

// A session (lockstep unless told otherwise) with the DDS interface on `domain`: the simulated ViSHaRD3 in admittance
// display with the virtual coupling, pushed by a scripted force.
inline std::string session_yaml(int domain, double duration_s, const std::string& force_profile,
                                const std::string& force_n, const std::string& clock = "lockstep",
                                const std::string& safety = "") {
  return "server: {clock: " + clock +
         ", seed: 11, realtime_priority: 0, lock_memory: false, duration_s: " + std::to_string(duration_s) + "}\n" +
         "dds: {domain_id: " + std::to_string(domain) + ", lockstep_start_wait_s: 20, lockstep_wait_s: 2}\n" +
         "devices:\n" + test::sim_vishard3_device_yaml("v3", force_profile, force_n) +
         "        wrench_force_start_s: 0.3\n" + coupling_chain_yaml() + "    safety: {" + safety +
         (clock == "realtime" ? std::string(safety.empty() ? "" : ", ") + kRealtimeWatchdogs : "") + "}\n";
}

// The session served as `hapticd` serves it (app/served_session), never asking for real-time scheduling, with a
// recording listener ahead of the DDS interface's.
class Server {
 public:
  explicit Server(const std::string& yaml) : session_(test::build_test_session(yaml)) {
    served_ = std::make_unique<ServedSession>(session_.impl().config, session_.impl().device_pointers(),
                                              session_.impl().stage_pointers(),
                                              ServeOptions{{}, /*realtime_setup=*/false, nullptr});
    listener_ = std::make_unique<RecordingListener>(served_->cycle_listener(), &device());
    served_->set_cycle_listener(listener_.get());
  }
  ~Server() {
    stop();  // a failed check must not wait for the session's end
    join();
  }
  void start() {
    thread_ = std::thread([this] { result_ = served_->run(stop_); });
  }
  // Ends the session now (the device stops through its safe mode); the real-time tests stop when their checks
  // are done.
  void stop() { stop_.store(true); }
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  DdsBridge& bridge() { return *served_->bridge(); }
  DeviceSession& device() { return *session_.impl().devices[0]; }
  const RecordingListener& recording() const { return *listener_; }
  const ExecutorResult& result() const { return result_; }
  const SessionMonitor& monitor() const { return served_->monitor(); }

 private:
  server::Session session_;
  std::unique_ptr<ServedSession> served_;
  std::unique_ptr<RecordingListener> listener_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  ExecutorResult result_;
};

// The scene engine of examples/engines: answers every state with the proxy of the handle in the scene.
struct SceneEngine {
  SceneEngine(int domain, const std::string& id) : client({id, domain}) {}
  ~SceneEngine() { client.on_state({}); }  // before the members the callback uses are gone
  SceneEngine(const SceneEngine&) = delete;
  SceneEngine& operator=(const SceneEngine&) = delete;
  bool connect() {
    if (!client.wait_for_state("v3", std::chrono::seconds(20))) return false;
    // The scene sits at the device's start pose (from the description, re-sent once the loop has run).
    const auto described = client.wait_for_device("v3", std::chrono::seconds(5), true);
    if (!described) return false;
    origin = described->start_pose->position;
    if (!client.claim("v3", std::chrono::seconds(10)).accepted) return false;
    client.on_state([this](const client::DeviceState& s) {
      if (!answering.load()) return;
      const Eigen::Vector3d x = s.target_pose.position - origin;  // the virtual body
      const Eigen::Vector3d p = scene.proxy(x);
      depth = std::max(depth.load(), (p - x).norm());
      Pose proxy = s.pose;
      proxy.position = origin + p;
      Twist twist;  // slides with the handle along a surface, never into it
      twist.linear = scene.proxy_velocity(x, p, s.twist.linear);
      client.send_coupling("v3", proxy, twist, s.serial);
    });
    return true;
  }
  Client client;
  examples::Scene scene = examples::demo_scene();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::atomic<double> depth{0.0};
  std::atomic<bool> answering{true};
};

}  // namespace hapticd::server::e2e
