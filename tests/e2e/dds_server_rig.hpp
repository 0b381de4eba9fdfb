#pragma once
// The end-to-end rig over DDS: a server (a session served as `hapticd` serves it, in this process, its own DDS
// participant) and the scene engine of clients/engines on the client library (a participant of its own), on a
// test domain of their own with the loopback-only configuration. Lockstep runs wait for the engine's answer to
// every state (dds.lockstep_sync), so they are repeatable; a recording listener on the loop thread captures what
// the device renders in every cycle.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "../../clients/engines/scene.hpp"
#include "app/served_session.hpp"
#include "hapticd/client/client.hpp"
#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/endpoints.hpp"
#include "hapticd_msg.h"
#include "support/sanitizers.hpp"
#include "support/test_session.hpp"

namespace hapticd::server::e2e {

using client::Client;

// Records, on the loop thread, the environment force the device renders and the handle position each cycle.
class RecordingListener final : public CycleListener {
 public:
  RecordingListener(CycleListener* next, DeviceSession* device) : next_(next), device_(device) {
    force_.reserve(20000);
    position_.reserve(20000);
    operator_force_.reserve(20000);
    weight_.reserve(20000);
    index_.reserve(20000);
  }
  void after_cycle(std::uint64_t index, bool lockstep) noexcept override {
    index_.push_back(index);
    force_.push_back(device_->task().wrench.force);
    position_.push_back(device_->chain_state().handle_pose.position);
    operator_force_.push_back(device_->chain_state().operator_wrench.force);
    weight_.push_back(device_->engine_weight());
    if (device_->command().torque_nm.size() > 0)
      peak_torque_ = std::max(peak_torque_, device_->command().torque_nm.cwiseAbs().maxCoeff());
    next_->after_cycle(index, lockstep);
  }
  const std::vector<Eigen::Vector3d>& force() const { return force_; }
  const std::vector<Eigen::Vector3d>& position() const { return position_; }
  // What the operator's hand applies to the handle (the sensor), each cycle: the force on the hand.
  const std::vector<Eigen::Vector3d>& operator_force() const { return operator_force_; }
  const std::vector<double>& engine_weight() const { return weight_; }
  // The largest joint torque commanded in any cycle (N m).
  double peak_torque() const { return peak_torque_; }
  // The loop's period index of each recorded cycle (a real-time loop that fell behind skips periods).
  const std::vector<std::uint64_t>& index() const { return index_; }

 private:
  CycleListener* next_;
  DeviceSession* device_;
  std::vector<Eigen::Vector3d> force_, position_, operator_force_;
  std::vector<double> weight_;
  std::vector<std::uint64_t> index_;
  double peak_torque_ = 0.0;
};

// Under a sanitizer the real-time loop runs several times slower than its period: the overrun watchdog (a
// device fault after 10 consecutive overruns) is off there, these runs look for races, not for timing.
using hapticd::test::kSanitized;

// The loop watchdogs of the real-time tests here, which test the DDS path, not the machine: loosened as in
// tests/e2e/session_copy.sh (why: there) - a shared CI machine runs the loop late now and then, for over 0.1 s
// in bursts. Under a sanitizer the loop runs several times slower than its period: the watchdogs are off there.
inline const std::string kRealtimeWatchdogs =
    kSanitized ? "max_consecutive_overruns: off, max_stall_s: off" : "max_consecutive_overruns: 2000, max_stall_s: 1.0";

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
  Doors& bridge() { return *served_->doors(); }  // the gate and its doors
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

// The scene engine of clients/engines: answers every state with the proxy of the handle in the scene.
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

// A hostile client built from the IDL alone: one DDS participant that sends requests under any client id it
// likes (the client library has one id per participant) and reads its replies.
class RawRequester {
 public:
  explicit RawRequester(int domain) : participant_(dds::ParticipantOptions{domain, {}, {}}), replies_(participant_) {}
  struct Answer {
    bool answered = false;
    bool accepted = false;
    std::string message;
  };
  // Sends the request (to `target`'s partition, as the client library does) and waits at most `timeout_s` for
  // its reply; sent again every 0.2 s until answered (the server answers a repeat, applies it once).
  Answer request(const std::string& target, hapticd_msg_RequestKind kind, const std::string& client,
                 const std::string& subject = {}, const std::vector<double>& values = {}, double timeout_s = 5.0) {
    const hapticd_msg_ControlRequest r = make(target, kind, client, subject, values);
    auto& writer = writer_for(target);
    (void)drain();  // replies to earlier requests (this client's or others')
    const auto start = std::chrono::steady_clock::now();
    const auto elapsed = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    while (writer.matched() == 0 && elapsed() < timeout_s) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    double sent_at = -1.0;
    while (elapsed() < timeout_s) {
      if (sent_at < 0.0 || elapsed() - sent_at > 0.2) {
        (void)writer.write(r);
        sent_at = elapsed();
      }
      Answer found;
      replies_.take([&](const hapticd_msg_ControlReply& m, const dds_sample_info_t&) {
        if (m.request_id == r.request_id && dds::text_of(m.client) == client)
          found = Answer{true, m.accepted, std::string(dds::text_of(m.message))};
      });
      if (found.answered) return found;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return {};
  }
  // Sends without waiting for the reply (a flood); the replies are read and dropped by drain().
  void send(const std::string& target, hapticd_msg_RequestKind kind, const std::string& client,
            const std::string& subject = {}) {
    (void)writer_for(target).write(make(target, kind, client, subject, {}));
  }
  int drain() {
    return replies_.take([](const hapticd_msg_ControlReply&, const dds_sample_info_t&) {});
  }
  [[nodiscard]] bool matched(const std::string& target) { return writer_for(target).matched() > 0; }

 private:
  hapticd_msg_ControlRequest make(const std::string& target, hapticd_msg_RequestKind kind, const std::string& client,
                                  const std::string& subject, const std::vector<double>& values) {
    hapticd_msg_ControlRequest r{};
    dds::set_text(r.device, target);
    dds::set_text(r.client, client);
    r.request_id = ++next_id_;
    r.kind = kind;
    dds::set_text(r.subject, subject);
    r.value_count = static_cast<std::int32_t>(std::min<std::size_t>(values.size(), hapticd_msg_MAX_VALUES));
    for (std::int32_t i = 0; i < r.value_count; ++i) r.values[i] = values[static_cast<std::size_t>(i)];
    return r;
  }
  dds::Writer<hapticd_msg_ControlRequest>& writer_for(const std::string& target) {
    auto& w = writers_[target];
    if (!w)
      w = std::make_unique<dds::Writer<hapticd_msg_ControlRequest>>(participant_, dds::CommandTiming{},
                                                                    dds::target_partition(target));
    return *w;
  }
  dds::Participant participant_;
  dds::Reader<hapticd_msg_ControlReply> replies_;
  std::map<std::string, std::unique_ptr<dds::Writer<hapticd_msg_ControlRequest>>> writers_;
  // Request ids from a random point, as the client library's: a reply is matched by client id and request id,
  // and every reader of a device's replies sees them all.
  std::uint64_t next_id_ = (std::uint64_t{std::random_device{}()} << 32) | std::random_device{}();
};

}  // namespace hapticd::server::e2e
