#include "hapticd/client/client.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstring>
#include <map>
#include <mutex>
#include <random>
#include <thread>

#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/endpoints.hpp"

namespace hapticd::client {

struct Client::Impl {
  explicit Impl(ClientOptions o)
      : options(std::move(o)),
        participant(dds::ParticipantOptions{options.domain_id, options.cyclone_config}),
        timing{options.command_deadline_s, 0.5},
        description(participant),
        state(participant),
        event(participant),
        telemetry(participant),
        fault_report(participant),
        reply(participant),
        group_description(participant),
        group_state(participant),
        command(participant, timing),
        group_command(participant, timing),
        request(participant),
        waitset(dds::check(dds_create_waitset(participant.get()), "cannot create a DDS waitset")),
        wake(dds::check(dds_create_guardcondition(participant.get()), "cannot create a DDS guard condition")) {
    for (dds_entity_t r :
         {description.get(), event.get(), telemetry.get(), fault_report.get(), reply.get(), group_description.get()}) {
      dds::check(dds_set_status_mask(r, DDS_DATA_AVAILABLE_STATUS), "status mask");
      dds::check(dds_waitset_attach(waitset.get(), r, r), "waitset");
    }
    dds::check(dds_waitset_attach(waitset.get(), wake.get(), wake.get()), "waitset");
    thread = std::thread([this] { run(); });
    // States are taken on Cyclone's receive thread (a listener): an engine answers without a thread wake-up.
    // Last: the listener may run at once, and needs everything above.
    const dds::Listener listener(dds_create_listener(this));
    dds_lset_data_available(listener.get(), [](dds_entity_t, void* arg) { static_cast<Impl*>(arg)->take_states(); });
    state.set_listener(listener.get());
    const dds::Listener group_listener(dds_create_listener(this));
    dds_lset_data_available(group_listener.get(),
                            [](dds_entity_t, void* arg) { static_cast<Impl*>(arg)->take_group_states(); });
    group_state.set_listener(group_listener.get());
  }
  ~Impl() {
    stopping.store(true);
    (void)dds_set_guardcondition(wake.get(), true);
    thread.join();
    // No more state callbacks (Cyclone waits for a running one; a local writer's thread may be in it), then
    // synchronise with the last one through our own locks, which ThreadSanitizer sees (Cyclone's it does not).
    (void)dds_set_listener(state.get(), nullptr);
    (void)dds_set_listener(group_state.get(), nullptr);
    std::lock_guard take(state_take_mutex);
    std::lock_guard lock(mutex);
  }

  void take_group_states() {
    std::lock_guard one_at_a_time(state_take_mutex);
    group_state.take([&](const hapticd_msg_GroupState& g, const dds_sample_info_t&) {
      {
        std::lock_guard lock(mutex);
        store_group_state(g);
      }
      if (waiters.load(std::memory_order_acquire) > 0) changed.notify_all();
      std::lock_guard lock(callback_mutex);
      if (group_state_callback) group_state_callback(g);
    });
  }

  void take_states() {
    std::lock_guard one_at_a_time(state_take_mutex);
    state.take([&](const hapticd_msg_DeviceState& s, const dds_sample_info_t&) {
      {
        std::lock_guard lock(mutex);
        store_state(s);
      }
      if (waiters.load(std::memory_order_acquire) > 0) changed.notify_all();
      std::lock_guard lock(callback_mutex);
      if (state_callback) state_callback(s);
    });
  }

  void run() {
    std::array<dds_attach_t, 8> triggered{};
    while (!stopping.load()) {
      (void)dds_waitset_wait(waitset.get(), triggered.data(), triggered.size(), DDS_MSECS(100));
      description.take([&](const hapticd_msg_DeviceDescription& d, const dds_sample_info_t&) {
        {
          std::lock_guard lock(mutex);
          descriptions[std::string(dds::text_of(d.device))] = d;
        }
        changed.notify_all();
      });
      group_description.take([&](const hapticd_msg_GroupDescription& g, const dds_sample_info_t&) {
        {
          std::lock_guard lock(mutex);
          group_descriptions[std::string(dds::text_of(g.group))] = g;
        }
        changed.notify_all();
      });
      reply.take([&](const hapticd_msg_ControlReply& r, const dds_sample_info_t&) {
        if (dds::text_of(r.client) != options.client_id) return;
        {
          std::lock_guard lock(mutex);
          Reply answer{true, r.accepted, std::string(dds::text_of(r.message)), {}};
          const auto count =
              static_cast<std::size_t>(std::clamp<std::int32_t>(r.value_count, 0, hapticd_msg_MAX_VALUES));
          answer.values.assign(r.values, r.values + count);
          replies[r.request_id] = std::move(answer);
        }
        changed.notify_all();
      });
      event.take([&](const hapticd_msg_Event& e, const dds_sample_info_t&) {
        std::function<void(const hapticd_msg_Event&)> f;
        {
          std::lock_guard lock(callback_mutex);
          f = event_callback;
        }
        if (f) f(e);
      });
      telemetry.take([&](const hapticd_msg_Telemetry& t, const dds_sample_info_t&) {
        std::function<void(const hapticd_msg_Telemetry&)> f;
        {
          std::lock_guard lock(callback_mutex);
          f = telemetry_callback;
        }
        if (f) f(t);
      });
      fault_report.take([&](const hapticd_msg_FaultReport& r, const dds_sample_info_t&) {
        std::function<void(const hapticd_msg_FaultReport&)> f;
        {
          // Kept with the choice of callback, under one lock: a callback set later gets it replayed exactly once.
          std::lock_guard lock(callback_mutex);
          auto& kept = fault_reports[std::string(dds::text_of(r.device))];
          if (!kept) kept = std::make_unique<hapticd_msg_FaultReport>();
          *kept = r;
          f = fault_report_callback;
        }
        if (f) f(r);
      });
    }
  }

  ClientOptions options;
  mutable std::mutex mutex;
  std::condition_variable changed;
  std::map<std::string, hapticd_msg_DeviceDescription> descriptions;
  // The newest state per device: a short list, searched by name (no allocation on the state path).
  std::vector<hapticd_msg_DeviceState> states;
  std::atomic<int> waiters{0};  // threads in a wait_for_*: only then does a state notify
  void store_state(const hapticd_msg_DeviceState& s) {
    for (auto& known : states)
      if (std::strncmp(known.device, s.device, sizeof s.device) == 0) {
        known = s;
        return;
      }
    states.push_back(s);
  }
  const hapticd_msg_DeviceState* find_state(std::string_view device) const {
    for (const auto& known : states)
      if (dds::text_of(known.device) == device) return &known;
    return nullptr;
  }
  std::map<std::string, hapticd_msg_GroupDescription> group_descriptions;
  // The newest state per group (each about 7 kB; allocated once per group).
  std::vector<std::unique_ptr<hapticd_msg_GroupState>> group_states;
  void store_group_state(const hapticd_msg_GroupState& g) {
    for (auto& known : group_states)
      if (std::strncmp(known->group, g.group, sizeof g.group) == 0) {
        *known = g;
        return;
      }
    group_states.push_back(std::make_unique<hapticd_msg_GroupState>(g));
  }
  const hapticd_msg_GroupState* find_group_state(std::string_view group) const {
    for (const auto& known : group_states)
      if (dds::text_of(known->group) == group) return known.get();
    return nullptr;
  }
  std::map<std::uint64_t, Reply> replies;
  // Request ids start at a random point: replies are matched by (client id, request id), and two clients that
  // declare the same id must not take each other's replies.
  std::atomic<std::uint64_t> next_request{std::random_device{}() | (std::uint64_t{std::random_device{}()} << 32) | 1};
  std::atomic<std::uint64_t> serial{0};

  std::mutex callback_mutex;
  std::function<void(const hapticd_msg_DeviceState&)> state_callback;
  std::function<void(const hapticd_msg_Event&)> event_callback;
  std::function<void(const hapticd_msg_Telemetry&)> telemetry_callback;
  std::function<void(const hapticd_msg_FaultReport&)> fault_report_callback;
  std::function<void(const hapticd_msg_GroupState&)> group_state_callback;
  std::map<std::string, std::unique_ptr<hapticd_msg_FaultReport>>
      fault_reports;  // the newest per device (~100 kB each)
  std::mutex state_take_mutex;
  dds::Participant participant;
  dds::CommandTiming timing;
  dds::Reader<hapticd_msg_DeviceDescription> description;
  dds::Reader<hapticd_msg_DeviceState> state;
  dds::Reader<hapticd_msg_Event> event;
  dds::Reader<hapticd_msg_Telemetry> telemetry;
  dds::Reader<hapticd_msg_FaultReport> fault_report;
  dds::Reader<hapticd_msg_ControlReply> reply;
  dds::Reader<hapticd_msg_GroupDescription> group_description;
  dds::Reader<hapticd_msg_GroupState> group_state;
  dds::Writer<hapticd_msg_EngineCommand> command;
  dds::Writer<hapticd_msg_GroupCommand> group_command;
  dds::Writer<hapticd_msg_ControlRequest> request;
  dds::Entity waitset, wake;
  std::thread thread;
  std::atomic<bool> stopping{false};
};

Client::Client(ClientOptions options) {
  if (options.client_id.empty() || options.client_id.size() > 31)
    throw std::invalid_argument("a client id of 1..31 characters is needed");
  impl_ = std::make_unique<Impl>(std::move(options));
}
Client::~Client() = default;

const std::string& Client::id() const noexcept { return impl_->options.client_id; }

std::vector<hapticd_msg_DeviceDescription> Client::devices() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<hapticd_msg_DeviceDescription> v;
  for (const auto& [name, d] : impl_->descriptions) v.push_back(d);
  return v;
}

std::optional<hapticd_msg_DeviceDescription> Client::wait_for_device(std::string_view device, Timeout timeout,
                                                                     bool started) {
  std::unique_lock lock(impl_->mutex);
  const std::string key(device);
  const auto ready = [&] {
    const auto it = impl_->descriptions.find(key);
    if (it == impl_->descriptions.end()) return false;
    const double* q = it->second.start_pose.orientation;
    return !started || q[0] != 0.0 || q[1] != 0.0 || q[2] != 0.0 || q[3] != 0.0;
  };
  if (!impl_->changed.wait_for(lock, timeout, ready)) return std::nullopt;
  return impl_->descriptions[key];
}

std::optional<hapticd_msg_DeviceState> Client::latest_state(std::string_view device) const {
  std::lock_guard lock(impl_->mutex);
  const hapticd_msg_DeviceState* s = impl_->find_state(device);
  if (s == nullptr) return std::nullopt;
  return *s;
}

std::optional<hapticd_msg_DeviceState> Client::wait_for_state(std::string_view device, Timeout timeout,
                                                              std::uint64_t after) {
  std::unique_lock lock(impl_->mutex);
  const std::string key(device);
  impl_->waiters.fetch_add(1);
  const bool got = impl_->changed.wait_for(lock, timeout, [&] {
    const hapticd_msg_DeviceState* s = impl_->find_state(key);
    return s != nullptr && s->serial > after;
  });
  impl_->waiters.fetch_sub(1);
  if (!got) return std::nullopt;
  return *impl_->find_state(key);
}

std::vector<hapticd_msg_GroupDescription> Client::groups() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<hapticd_msg_GroupDescription> v;
  for (const auto& [name, g] : impl_->group_descriptions) v.push_back(g);
  return v;
}

std::optional<hapticd_msg_GroupDescription> Client::wait_for_group(std::string_view group, Timeout timeout) {
  std::unique_lock lock(impl_->mutex);
  const std::string key(group);
  if (!impl_->changed.wait_for(lock, timeout, [&] { return impl_->group_descriptions.count(key) > 0; }))
    return std::nullopt;
  return impl_->group_descriptions[key];
}

std::unique_ptr<hapticd_msg_GroupState> Client::latest_group_state(std::string_view group) const {
  std::lock_guard lock(impl_->mutex);
  const hapticd_msg_GroupState* g = impl_->find_group_state(group);
  if (g == nullptr) return nullptr;
  return std::make_unique<hapticd_msg_GroupState>(*g);
}

std::unique_ptr<hapticd_msg_GroupState> Client::wait_for_group_state(std::string_view group, Timeout timeout,
                                                                     std::uint64_t after) {
  std::unique_lock lock(impl_->mutex);
  const std::string key(group);
  impl_->waiters.fetch_add(1);
  const bool got = impl_->changed.wait_for(lock, timeout, [&] {
    const hapticd_msg_GroupState* g = impl_->find_group_state(key);
    return g != nullptr && g->serial > after;
  });
  impl_->waiters.fetch_sub(1);
  if (!got) return nullptr;
  return std::make_unique<hapticd_msg_GroupState>(*impl_->find_group_state(key));
}

void Client::on_group_state(std::function<void(const hapticd_msg_GroupState&)> callback) {
  std::lock_guard lock(impl_->callback_mutex);
  impl_->group_state_callback = std::move(callback);
}

void Client::on_state(std::function<void(const hapticd_msg_DeviceState&)> callback) {
  std::lock_guard lock(impl_->callback_mutex);
  impl_->state_callback = std::move(callback);
}
void Client::on_event(std::function<void(const hapticd_msg_Event&)> callback) {
  std::lock_guard lock(impl_->callback_mutex);
  impl_->event_callback = std::move(callback);
}
void Client::on_telemetry(std::function<void(const hapticd_msg_Telemetry&)> callback) {
  std::lock_guard lock(impl_->callback_mutex);
  impl_->telemetry_callback = std::move(callback);
}

void Client::on_fault_report(std::function<void(const hapticd_msg_FaultReport&)> callback) {
  std::vector<std::unique_ptr<hapticd_msg_FaultReport>> received;
  {
    std::lock_guard lock(impl_->callback_mutex);
    impl_->fault_report_callback = callback;
    if (callback)
      for (const auto& [device, r] : impl_->fault_reports)
        received.push_back(std::make_unique<hapticd_msg_FaultReport>(*r));
  }
  for (const auto& r : received) callback(*r);  // those that arrived before (a late joiner's transient-local ones)
}

std::unique_ptr<hapticd_msg_FaultReport> Client::latest_fault_report(std::string_view device) const {
  std::lock_guard lock(impl_->callback_mutex);
  const auto it = impl_->fault_reports.find(std::string(device));
  if (it == impl_->fault_reports.end()) return nullptr;
  return std::make_unique<hapticd_msg_FaultReport>(*it->second);
}

Reply Client::request(std::string_view device, hapticd_msg_RequestKind kind, std::string_view name,
                      const std::vector<double>& values, Timeout timeout) {
  hapticd_msg_ControlRequest r{};
  dds::set_text(r.device, device);
  dds::set_text(r.client, impl_->options.client_id);
  r.request_id = impl_->next_request.fetch_add(1);
  r.kind = kind;
  dds::set_text(r.name, name);
  r.value_count = static_cast<std::int32_t>(std::min<std::size_t>(values.size(), hapticd_msg_MAX_VALUES));
  for (std::int32_t i = 0; i < r.value_count; ++i) r.values[i] = values[static_cast<std::size_t>(i)];
  // A reliable writer delivers to the readers it has matched: give discovery a moment after start-up.
  const auto until =
      std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(timeout);
  while (impl_->request.matched() == 0 && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  if (!impl_->request.write(r)) return Reply{false, false, "cannot write the request", {}};
  std::unique_lock lock(impl_->mutex);
  if (!impl_->changed.wait_until(lock, until, [&] { return impl_->replies.count(r.request_id) > 0; }))
    return Reply{false, false, "no reply within the timeout", {}};
  Reply reply = impl_->replies[r.request_id];
  impl_->replies.erase(r.request_id);
  return reply;
}

Reply Client::claim(std::string_view device, Timeout timeout) {
  Reply r = request(device, hapticd_msg_REQUEST_CLAIM, {}, {}, timeout);
  if (r.accepted) reset_serial();
  return r;
}
Reply Client::release(std::string_view device, Timeout timeout) {
  return request(device, hapticd_msg_REQUEST_RELEASE, {}, {}, timeout);
}
Reply Client::switch_scheme(std::string_view device, std::string_view scheme, Timeout timeout) {
  return request(device, hapticd_msg_REQUEST_SWITCH_SCHEME, scheme, {}, timeout);
}
Reply Client::set_parameter(std::string_view device, std::string_view parameter, const std::vector<double>& values,
                            Timeout timeout) {
  return request(device, hapticd_msg_REQUEST_SET_PARAMETER, parameter, values, timeout);
}
Reply Client::get_parameter(std::string_view device, std::string_view parameter, Timeout timeout) {
  return request(device, hapticd_msg_REQUEST_GET_PARAMETER, parameter, {}, timeout);
}
Reply Client::emergency_stop(std::string_view device, Timeout timeout) {
  return request(device, hapticd_msg_REQUEST_ESTOP, {}, {}, timeout);
}
Reply Client::recover(std::string_view device, Timeout timeout) {
  return request(device, hapticd_msg_REQUEST_RECOVER, {}, {}, timeout);
}
Reply Client::operator_command(std::string_view device, std::string_view command, const std::vector<double>& values,
                               Timeout timeout) {
  return request(device, hapticd_msg_REQUEST_OPERATOR, command, values, timeout);
}

Reply Client::claim_group(std::string_view group, Timeout timeout) {
  Reply r = request(group, hapticd_msg_REQUEST_GROUP_CLAIM, {}, {}, timeout);
  if (r.accepted) reset_serial();
  return r;
}
Reply Client::release_group(std::string_view group, Timeout timeout) {
  return request(group, hapticd_msg_REQUEST_GROUP_RELEASE, {}, {}, timeout);
}
Reply Client::emergency_stop_group(std::string_view group, Timeout timeout) {
  return request(group, hapticd_msg_REQUEST_GROUP_ESTOP, {}, {}, timeout);
}
Reply Client::recover_group(std::string_view group, Timeout timeout) {
  return request(group, hapticd_msg_REQUEST_GROUP_RECOVER, {}, {}, timeout);
}

bool Client::send(std::string_view device, hapticd_msg_EngineCommand& command) {
  dds::set_text(command.device, device);
  dds::set_text(command.engine, impl_->options.client_id);
  command.serial = impl_->serial.fetch_add(1) + 1;
  return impl_->command.write(command);
}

bool Client::send_group(std::string_view group, std::span<hapticd_msg_EngineCommand> commands) {
  if (commands.size() > static_cast<std::size_t>(hapticd_msg_MAX_GROUP_DEVICES)) return false;
  auto g = std::make_unique<hapticd_msg_GroupCommand>();  // about 5 kB
  dds::set_text(g->group, group);
  g->command_count = static_cast<std::int32_t>(commands.size());
  for (std::size_t k = 0; k < commands.size(); ++k) {
    dds::set_text(commands[k].engine, impl_->options.client_id);
    commands[k].serial = impl_->serial.fetch_add(1) + 1;
    g->commands[k] = commands[k];
  }
  return impl_->group_command.write(*g);
}

namespace {
hapticd_msg_EngineCommand pose_command(hapticd_msg_CommandKind kind, const Pose& pose, const Twist& twist,
                                       std::uint64_t state_serial) {
  hapticd_msg_EngineCommand c{};
  c.kind = kind;
  c.state_serial = state_serial;
  dds::to_msg(pose, c.pose);
  dds::to_msg(twist, c.twist);
  c.anchor.orientation[0] = 1.0;
  return c;
}
}  // namespace

hapticd_msg_EngineCommand coupling_command(std::string_view device, const Pose& proxy, const Twist& proxy_twist,
                                           std::uint64_t state_serial) {
  hapticd_msg_EngineCommand c = pose_command(hapticd_msg_COMMAND_COUPLING, proxy, proxy_twist, state_serial);
  dds::set_text(c.device, device);
  return c;
}

bool Client::send_coupling(std::string_view device, const Pose& proxy, const Twist& proxy_twist,
                           std::uint64_t state_serial) {
  hapticd_msg_EngineCommand c = pose_command(hapticd_msg_COMMAND_COUPLING, proxy, proxy_twist, state_serial);
  return send(device, c);
}

bool Client::send_wrench(std::string_view device, const Wrench& wrench, std::uint64_t state_serial) {
  hapticd_msg_EngineCommand c{};
  c.kind = hapticd_msg_COMMAND_WRENCH;
  c.state_serial = state_serial;
  dds::to_msg(wrench, c.wrench);
  c.anchor.orientation[0] = 1.0;
  c.pose.orientation[0] = 1.0;
  return send(device, c);
}

bool Client::send_motion(std::string_view device, const Pose& pose, const Twist& twist, std::uint64_t state_serial) {
  hapticd_msg_EngineCommand c = pose_command(hapticd_msg_COMMAND_MOTION, pose, twist, state_serial);
  return send(device, c);
}

void Client::reset_serial() noexcept { impl_->serial.store(0); }

std::string_view name_of(const hapticd_msg_Name& name) noexcept { return dds::text_of(name); }
std::string_view name_of(const hapticd_msg_Text& text) noexcept { return dds::text_of(text); }
Pose pose_of(const hapticd_msg_Pose& pose) noexcept { return dds::to_pose(pose); }
Twist twist_of(const double (&t)[6]) noexcept {
  Twist r;
  r.linear = Eigen::Vector3d(t[0], t[1], t[2]);
  r.angular = Eigen::Vector3d(t[3], t[4], t[5]);
  return r;
}
Wrench wrench_of(const double (&w)[6]) noexcept {
  Wrench r;
  r.force = Eigen::Vector3d(w[0], w[1], w[2]);
  r.torque = Eigen::Vector3d(w[3], w[4], w[5]);
  return r;
}

}  // namespace hapticd::client
