#include "hapticd/client/client.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <thread>

#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/endpoints.hpp"
#include "request_timing.hpp"
#include "scene_wire.hpp"
#include "wire.hpp"

namespace hapticd::client {

namespace {

// A writer in a target's partition, or none where the domain's DDS Security permissions do not let this identity
// publish the topic there.
template <class T>
std::unique_ptr<dds::Writer<T>> permitted(const dds::Participant& participant, const dds::CommandTiming& timing,
                                          std::string_view target) {
  try {
    return std::make_unique<dds::Writer<T>>(participant, timing, dds::target_partition(target));
  } catch (const dds::Error& e) {
    if (e.code() != DDS_RETCODE_NOT_ALLOWED_BY_SECURITY) throw;
    return nullptr;
  }
}

// What a client writes to one device or group, in its partition (dds::target_partition); made on first use.
struct TargetWriters {
  std::unique_ptr<dds::Writer<hapticd_msg_ControlRequest>> request;
  std::unique_ptr<dds::Writer<hapticd_msg_EngineCommand>> command;
  std::unique_ptr<dds::Writer<hapticd_msg_GroupCommand>> group_command;
  bool made_request = false, made_command = false, made_group_command = false;
};
}  // namespace

struct Client::Impl {
  explicit Impl(ClientOptions o)
      : options(std::move(o)),
        participant(dds::ParticipantOptions{
            options.domain_id, options.cyclone_config,
            options.network.empty() ? std::nullopt : std::optional(dds::parse_network(options.network))}),
        timing{options.command_deadline_s, 0.5},
        description(participant),
        state(participant),
        event(participant),
        telemetry(participant),
        fault_report(participant),
        reply(participant),
        group_description(participant),
        group_state(participant),
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

  // Receive thread. The converted sample lives in the Impl (a group state is several kB): no allocation.
  void take_group_states() {
    std::lock_guard one_at_a_time(state_take_mutex);
    group_state.take([&](const hapticd_msg_GroupState& g, const dds_sample_info_t&) {
      wire::from_msg(g, group_scratch);
      {
        std::lock_guard lock(mutex);
        store(group_states, group_scratch, &GroupState::group);
      }
      if (waiters.load(std::memory_order_acquire) > 0) changed.notify_all();
      std::lock_guard lock(callback_mutex);
      if (group_state_callback) group_state_callback(group_scratch);
    });
  }

  void take_states() {
    std::lock_guard one_at_a_time(state_take_mutex);
    state.take([&](const hapticd_msg_DeviceState& s, const dds_sample_info_t&) {
      wire::from_msg(s, state_scratch);
      const ClaimWatch* lost = nullptr;
      {
        std::lock_guard lock(mutex);
        store(states, state_scratch, &DeviceState::device);
        lost = watch_claim(state_scratch);
      }
      if (waiters.load(std::memory_order_acquire) > 0) changed.notify_all();
      std::lock_guard lock(callback_mutex);
      if (lost != nullptr) tell_claim_lost(state_scratch.device.view(), state_scratch.owner.view());
      if (state_callback) state_callback(state_scratch);
    });
  }

  // The claims this client holds, watched in the states and in the owner events (fixed capacity: no allocation
  // on the receive thread). Each stream comes in order from one writer, but the two are not ordered against each
  // other (a state taken before the claim may arrive after the event that announced it), so each has its own
  // "confirmed": a stream tells a loss only after it named this client. The events are reliable: an engine
  // stopped before it saw a state naming it still learns, once it runs again, that it had the claim and lost it.
  struct ClaimWatch {
    Name device;
    bool active = false;
    bool confirmed_by_state = false;  // a state named this client as the owner
    bool confirmed_by_event = false;  // an owner event did
    bool lost = false;
  };
  static constexpr std::size_t kWatchedClaims = 16;
  std::array<ClaimWatch, kWatchedClaims> claims{};
  // Under `mutex`: a device's owner as a state or an owner event names it. Another owner after this client in the
  // same stream: lost (once).
  const ClaimWatch* watch_owner(std::string_view device, std::string_view owner, bool from_event) {
    for (ClaimWatch& w : claims) {
      if (!w.active || !(w.device == device)) continue;
      bool& confirmed = from_event ? w.confirmed_by_event : w.confirmed_by_state;
      if (owner == options.client_id) {
        confirmed = true;
      } else if (confirmed && !w.lost) {
        w.lost = true;
        return &w;
      }
    }
    return nullptr;
  }
  const ClaimWatch* watch_claim(const DeviceState& s) { return watch_owner(s.device.view(), s.owner.view(), false); }
  // Under `callback_mutex`: the claim of `device` is lost; `owner` is who holds it now ("" nobody).
  void tell_claim_lost(std::string_view device, std::string_view owner) {
    if (claim_lost_callback)
      claim_lost_callback(
          device, owner.empty() ? "the server freed the device" : "the server handed the device to another owner");
  }
  void watch(std::string_view device, bool on) {
    std::lock_guard lock(mutex);
    ClaimWatch* free = nullptr;
    for (ClaimWatch& w : claims) {
      if (w.active && w.device == device) {
        w = on ? ClaimWatch{Name(device), true} : ClaimWatch{};
        return;
      }
      if (!w.active && free == nullptr) free = &w;
    }
    if (on && free != nullptr) *free = ClaimWatch{Name(device), true};
  }

  // The client's thread: descriptions, replies, events, telemetry, fault reports.
  void run() {
    std::array<dds_attach_t, 8> triggered{};
    while (!stopping.load()) {
      (void)dds_waitset_wait(waitset.get(), triggered.data(), triggered.size(), DDS_MSECS(100));
      description.take([&](const hapticd_msg_DeviceDescription& d, const dds_sample_info_t&) {
        DeviceInfo info = wire::from_msg(d);
        {
          std::lock_guard lock(mutex);
          descriptions[info.device] = std::move(info);
        }
        changed.notify_all();
      });
      group_description.take([&](const hapticd_msg_GroupDescription& g, const dds_sample_info_t&) {
        GroupInfo info = wire::from_msg(g);
        {
          std::lock_guard lock(mutex);
          group_descriptions[info.group] = std::move(info);
        }
        changed.notify_all();
      });
      reply.take([&](const hapticd_msg_ControlReply& r, const dds_sample_info_t&) {
        if (dds::text_of(r.client) != options.client_id) return;
        {
          std::lock_guard lock(mutex);
          if (!pending.contains(r.request_id)) return;  // another copy's reply, answered already
          Reply answer{true, r.accepted, std::string(dds::text_of(r.message)), {}};
          const auto count = static_cast<std::size_t>(std::clamp<std::int32_t>(r.value_count, 0, kMaxValues));
          answer.values.assign(r.values, r.values + count);
          replies[r.request_id] = std::move(answer);
        }
        changed.notify_all();
      });
      event.take([&](const hapticd_msg_Event& e, const dds_sample_info_t&) {
        const Event value = wire::from_msg(e);
        if (value.kind == EventKind::owner) {
          const ClaimWatch* lost = nullptr;
          {
            std::lock_guard lock(mutex);
            lost = watch_owner(value.device, value.code, true);
          }
          std::lock_guard lock(callback_mutex);
          if (lost != nullptr) tell_claim_lost(value.device, value.code);
        }
        std::function<void(const Event&)> f;
        {
          std::lock_guard lock(callback_mutex);
          f = event_callback;
          if (events.size() == kEventsKept) events.pop_front();
          events.push_back(value);
        }
        if (f) f(value);
      });
      telemetry.take([&](const hapticd_msg_Telemetry& t, const dds_sample_info_t&) {
        const Telemetry value = wire::from_msg(t);
        std::function<void(const Telemetry&)> f;
        {
          std::lock_guard lock(callback_mutex);
          f = telemetry_callback;
          telemetries[value.device] = value;
        }
        if (f) f(value);
      });
      fault_report.take([&](const hapticd_msg_FaultReport& r, const dds_sample_info_t&) {
        const FaultReport value = wire::from_msg(r);
        std::function<void(const FaultReport&)> f;
        {
          // Kept with the choice of callback, under one lock: a callback set later gets it replayed exactly once.
          std::lock_guard lock(callback_mutex);
          fault_reports[value.device] = value;
          f = fault_report_callback;
        }
        if (f) f(value);
      });
    }
  }

  // The newest sample per key: a short list searched by name (no allocation once every key was seen).
  template <class T>
  static void store(std::vector<T>& kept, const T& sample, Name T::*key) {
    for (auto& known : kept)
      if (known.*key == (sample.*key).view()) {
        known = sample;
        return;
      }
    kept.push_back(sample);
  }
  template <class T>
  static const T* find(const std::vector<T>& kept, std::string_view name, Name T::*key) {
    for (const auto& known : kept)
      if (known.*key == name) return &known;
    return nullptr;
  }

  template <class T>
  std::optional<T> wait_for(const std::vector<T>& kept, Name T::*key, std::string_view name, Timeout timeout,
                            std::uint64_t after) {
    std::unique_lock lock(mutex);
    waiters.fetch_add(1);
    const bool got = changed.wait_for(lock, countable(timeout), [&] {
      const T* s = find(kept, name, key);
      return s != nullptr && s->serial > after;
    });
    waiters.fetch_sub(1);
    if (!got) return std::nullopt;
    return *find(kept, name, key);
  }

  static constexpr std::size_t kEventsKept = 1024;

  ClientOptions options;
  mutable std::mutex mutex;
  std::condition_variable changed;
  std::map<std::string, DeviceInfo, std::less<>> descriptions;
  std::map<std::string, GroupInfo, std::less<>> group_descriptions;
  std::vector<DeviceState> states;
  std::vector<GroupState> group_states;
  DeviceState state_scratch;  // the receive thread's conversion targets
  GroupState group_scratch;
  std::atomic<int> waiters{0};  // threads in a wait_for_*: only then does a state notify
  std::map<std::uint64_t, Reply> replies;
  std::set<std::uint64_t> pending;  // requests waiting for their reply
  // Request ids start at a random point: replies are matched by (client id, request id), and two clients that
  // declare the same id must not take each other's replies.
  std::atomic<std::uint64_t> next_request{std::random_device{}() | (std::uint64_t{std::random_device{}()} << 32) | 1};
  std::atomic<std::uint64_t> serial{0};

  mutable std::mutex callback_mutex;
  std::function<void(const DeviceState&)> state_callback;
  std::function<void(const GroupState&)> group_state_callback;
  std::function<void(const Event&)> event_callback;
  std::function<void(const Telemetry&)> telemetry_callback;
  std::function<void(const FaultReport&)> fault_report_callback;
  std::function<void(std::string_view, std::string_view)> claim_lost_callback;
  std::deque<Event> events;  // for take_events
  std::map<std::string, Telemetry, std::less<>> telemetries;
  std::map<std::string, FaultReport, std::less<>> fault_reports;  // the newest per device
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
  // Per device or group, made on first use; a writer is absent where DDS Security does not permit this identity to
  // write it (a watcher, an engine of other devices): sending then fails.
  std::mutex writers_mutex;
  std::map<std::string, TargetWriters, std::less<>> writers;
  // The world's writer (publish_world), in the default partition, made on first use.
  std::mutex world_mutex;
  std::unique_ptr<dds::Writer<hapticd_msg_World>> world_writer;
  bool world_writer_made = false;
  std::uint64_t world_serial = 0;
  // The haptic scene's client (scene()), made on first use; before the participant goes.
  std::mutex scene_mutex;
  std::unique_ptr<SceneClient> scene;
  template <class T>
  dds::Writer<T>* writer(std::string_view target, std::unique_ptr<dds::Writer<T>> TargetWriters::*slot,
                         bool TargetWriters::*made) {
    std::lock_guard lock(writers_mutex);
    auto it = writers.find(target);
    if (it == writers.end()) it = writers.emplace(std::string(target), TargetWriters{}).first;
    TargetWriters& w = it->second;
    if (!(w.*made)) {
      w.*slot = permitted<T>(participant, timing, target);
      w.*made = true;
    }
    return (w.*slot).get();
  }
  dds::Writer<hapticd_msg_ControlRequest>* request_writer(std::string_view target) {
    return writer(target, &TargetWriters::request, &TargetWriters::made_request);
  }
  dds::Writer<hapticd_msg_EngineCommand>* command_writer(std::string_view target) {
    return writer(target, &TargetWriters::command, &TargetWriters::made_command);
  }
  dds::Writer<hapticd_msg_GroupCommand>* group_command_writer(std::string_view target) {
    return writer(target, &TargetWriters::group_command, &TargetWriters::made_group_command);
  }
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

std::vector<DeviceInfo> Client::devices() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<DeviceInfo> v;
  for (const auto& [name, d] : impl_->descriptions) v.push_back(d);
  return v;
}

std::optional<DeviceInfo> Client::wait_for_device(std::string_view device, Timeout timeout, bool started) {
  std::unique_lock lock(impl_->mutex);
  const auto ready = [&] {
    const auto it = impl_->descriptions.find(device);
    return it != impl_->descriptions.end() && (!started || it->second.start_pose.has_value());
  };
  if (!impl_->changed.wait_for(lock, countable(timeout), ready)) return std::nullopt;
  return impl_->descriptions.find(device)->second;
}

std::optional<DeviceState> Client::latest_state(std::string_view device) const {
  std::lock_guard lock(impl_->mutex);
  const DeviceState* s = Impl::find(impl_->states, device, &DeviceState::device);
  if (s == nullptr) return std::nullopt;
  return *s;
}

std::optional<DeviceState> Client::wait_for_state(std::string_view device, Timeout timeout, std::uint64_t after) {
  return impl_->wait_for(impl_->states, &DeviceState::device, device, timeout, after);
}

std::vector<GroupInfo> Client::groups() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<GroupInfo> v;
  for (const auto& [name, g] : impl_->group_descriptions) v.push_back(g);
  return v;
}

std::optional<GroupInfo> Client::wait_for_group(std::string_view group, Timeout timeout) {
  std::unique_lock lock(impl_->mutex);
  if (!impl_->changed.wait_for(lock, countable(timeout), [&] { return impl_->group_descriptions.contains(group); }))
    return std::nullopt;
  return impl_->group_descriptions.find(group)->second;
}

std::optional<GroupState> Client::latest_group_state(std::string_view group) const {
  std::lock_guard lock(impl_->mutex);
  const GroupState* g = Impl::find(impl_->group_states, group, &GroupState::group);
  if (g == nullptr) return std::nullopt;
  return *g;
}

std::optional<GroupState> Client::wait_for_group_state(std::string_view group, Timeout timeout, std::uint64_t after) {
  return impl_->wait_for(impl_->group_states, &GroupState::group, group, timeout, after);
}

std::vector<Event> Client::take_events() {
  std::lock_guard lock(impl_->callback_mutex);
  std::vector<Event> taken(std::make_move_iterator(impl_->events.begin()),
                           std::make_move_iterator(impl_->events.end()));
  impl_->events.clear();
  return taken;
}

std::optional<Telemetry> Client::latest_telemetry(std::string_view device) const {
  std::lock_guard lock(impl_->callback_mutex);
  const auto it = impl_->telemetries.find(device);
  if (it == impl_->telemetries.end()) return std::nullopt;
  return it->second;
}

std::optional<FaultReport> Client::latest_fault_report(std::string_view device) const {
  std::lock_guard lock(impl_->callback_mutex);
  const auto it = impl_->fault_reports.find(device);
  if (it == impl_->fault_reports.end()) return std::nullopt;
  return it->second;
}

void Client::on_state(std::function<void(const DeviceState&)> callback) {
  std::lock_guard lock(impl_->callback_mutex);
  impl_->state_callback = std::move(callback);
}
void Client::on_group_state(std::function<void(const GroupState&)> callback) {
  std::lock_guard lock(impl_->callback_mutex);
  impl_->group_state_callback = std::move(callback);
}
void Client::on_event(std::function<void(const Event&)> callback) {
  std::lock_guard lock(impl_->callback_mutex);
  impl_->event_callback = std::move(callback);
}
void Client::on_telemetry(std::function<void(const Telemetry&)> callback) {
  std::lock_guard lock(impl_->callback_mutex);
  impl_->telemetry_callback = std::move(callback);
}

void Client::on_fault_report(std::function<void(const FaultReport&)> callback) {
  std::vector<FaultReport> received;
  {
    std::lock_guard lock(impl_->callback_mutex);
    impl_->fault_report_callback = callback;
    if (callback)
      for (const auto& [device, r] : impl_->fault_reports) received.push_back(r);
  }
  for (const auto& r : received) callback(r);  // those that arrived before (a late joiner's transient-local ones)
}

Reply Client::request(std::string_view device, RequestKind kind, std::string_view name,
                      const std::vector<double>& values, Timeout timeout) {
  hapticd_msg_ControlRequest r{};
  dds::set_text(r.device, device);
  dds::set_text(r.client, impl_->options.client_id);
  r.request_id = impl_->next_request.fetch_add(1);
  r.kind = wire::to_msg(kind);
  dds::set_text(r.subject, name);
  r.value_count = static_cast<std::int32_t>(std::min<std::size_t>(values.size(), kMaxValues));
  for (std::int32_t i = 0; i < r.value_count; ++i) r.values[i] = values[static_cast<std::size_t>(i)];
  // A reliable writer delivers to the readers it has matched: give discovery a moment after start-up.
  const auto until = std::chrono::steady_clock::now() + countable(timeout);
  dds::Writer<hapticd_msg_ControlRequest>* writer = impl_->request_writer(device);
  if (writer == nullptr)
    return Reply{false,
                 false,
                 "this identity may not send requests to '" + std::string(device) + "' (DDS Security permissions)",
                 {}};
  while (writer->matched() == 0 && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  // Sent again, with the same id, every kRequestRetry without a reply: the server answers a repeated request
  // again and applies it once (the first may have arrived before discovery let the server know this
  // participant, or its reply before the server had matched our reply reader).
  std::unique_lock lock(impl_->mutex);
  impl_->pending.insert(r.request_id);
  struct Done {  // whatever the way out: no longer pending, no reply kept
    Impl& impl;
    std::uint64_t id;
    ~Done() {
      impl.pending.erase(id);
      impl.replies.erase(id);
    }
  } done{*impl_, r.request_id};
  const auto answered = [&] { return impl_->replies.count(r.request_id) > 0; };
  for (;;) {
    lock.unlock();
    const bool written = writer->write(r);
    lock.lock();
    if (!written && !answered()) return Reply{false, false, "cannot write the request", {}};
    const auto retry = std::min(until, std::chrono::steady_clock::now() + kRequestRetry);
    if (impl_->changed.wait_until(lock, retry, answered)) break;
    if (retry >= until) return Reply{false, false, "no reply within the timeout", {}};
  }
  return impl_->replies[r.request_id];
}

Reply Client::claim(std::string_view device, Timeout timeout) {
  (void)impl_->command_writer(device);  // made (and matched) while the claim is on its way
  impl_->watch(device, true);           // before the request: the event announcing the claim may come before the reply
  Reply r = request(device, RequestKind::claim, {}, {}, timeout);
  if (r.accepted)
    reset_serial();
  else
    impl_->watch(device, false);
  return r;
}
Reply Client::release(std::string_view device, Timeout timeout) {
  impl_->watch(device, false);  // a release ends the claim: no loss to tell
  return request(device, RequestKind::release, {}, {}, timeout);
}

void Client::on_claim_lost(std::function<void(std::string_view, std::string_view)> callback) {
  std::lock_guard lock(impl_->callback_mutex);
  impl_->claim_lost_callback = std::move(callback);
}

bool Client::claim_lost(std::string_view device) const {
  std::lock_guard lock(impl_->mutex);
  for (const Impl::ClaimWatch& w : impl_->claims)
    if (w.active && w.device == device) return w.lost;
  return false;
}
Reply Client::switch_scheme(std::string_view device, std::string_view scheme, Timeout timeout) {
  return request(device, RequestKind::switch_scheme, scheme, {}, timeout);
}
Reply Client::set_parameter(std::string_view device, std::string_view parameter, const std::vector<double>& values,
                            Timeout timeout) {
  return request(device, RequestKind::set_parameter, parameter, values, timeout);
}
Reply Client::get_parameter(std::string_view device, std::string_view parameter, Timeout timeout) {
  return request(device, RequestKind::get_parameter, parameter, {}, timeout);
}
Client::ParameterAnswer Client::describe_parameter(std::string_view device, std::string_view parameter,
                                                   Timeout timeout) {
  ParameterAnswer a{request(device, RequestKind::describe_parameter, parameter, {}, timeout), std::nullopt};
  if (!a.reply.accepted) return a;
  if (auto d = decode_parameter_info(a.reply.message, a.reply.values)) {
    a.info = std::move(d->info);
  } else {
    a.reply.accepted = false;
    a.reply.message =
        "the server's description of " + std::string(parameter) + " is not readable (\"" + a.reply.message + "\")";
  }
  return a;
}

Client::ParameterList Client::parameters(std::string_view device, Timeout timeout) {
  ParameterList list;
  for (std::size_t k = 0, count = 1; k < count; ++k) {
    list.reply = request(device, RequestKind::describe_parameter, {}, {static_cast<double>(k)}, timeout);
    if (!list.reply.accepted) return list;
    auto d = decode_parameter_info(list.reply.message, list.reply.values);
    if (!d) {
      list.reply.accepted = false;
      list.reply.message = "the server's description of parameter " + std::to_string(k) + " is not readable";
      return list;
    }
    count = d->count;
    list.parameters.push_back(std::move(d->info));
  }
  return list;
}
Reply Client::emergency_stop(std::string_view device, Timeout timeout) {
  return request(device, RequestKind::estop, {}, {}, timeout);
}
Reply Client::recover(std::string_view device, Timeout timeout) {
  return request(device, RequestKind::recover, {}, {}, timeout);
}
Reply Client::operator_command(std::string_view device, std::string_view command, const std::vector<double>& values,
                               Timeout timeout) {
  return request(device, RequestKind::operator_command, command, values, timeout);
}

Reply Client::claim_group(std::string_view group, Timeout timeout) {
  (void)impl_->group_command_writer(group);
  const std::vector<std::string> devices = group_devices(group);
  for (const std::string& d : devices) impl_->watch(d, true);  // before the request, as for claim()
  Reply r = request(group, RequestKind::group_claim, {}, {}, timeout);
  if (r.accepted)
    reset_serial();
  else
    for (const std::string& d : devices) impl_->watch(d, false);
  return r;
}
Reply Client::release_group(std::string_view group, Timeout timeout) {
  for (const std::string& d : group_devices(group)) impl_->watch(d, false);
  return request(group, RequestKind::group_release, {}, {}, timeout);
}

std::vector<std::string> Client::group_devices(std::string_view group) const {
  std::lock_guard lock(impl_->mutex);
  const auto found = impl_->group_descriptions.find(group);
  return found == impl_->group_descriptions.end() ? std::vector<std::string>{} : found->second.devices;
}
Reply Client::emergency_stop_group(std::string_view group, Timeout timeout) {
  return request(group, RequestKind::group_estop, {}, {}, timeout);
}
Reply Client::recover_group(std::string_view group, Timeout timeout) {
  return request(group, RequestKind::group_recover, {}, {}, timeout);
}

bool Client::send(std::string_view device, const EngineCommand& command) {
  hapticd_msg_EngineCommand c;
  wire::to_msg(command, device, c);
  dds::set_text(c.engine, impl_->options.client_id);
  c.serial = impl_->serial.fetch_add(1) + 1;
  dds::Writer<hapticd_msg_EngineCommand>* writer = impl_->command_writer(device);
  return writer != nullptr && writer->write(c);
}

SceneClient& Client::scene() {
  std::lock_guard lock(impl_->scene_mutex);
  if (!impl_->scene) impl_->scene = make_scene_client(impl_->participant, impl_->options.client_id);
  return *impl_->scene;
}

bool Client::publish_world(std::span<const WorldShape> shapes, double time_s) {
  if (shapes.size() > static_cast<std::size_t>(kMaxWorldShapes)) return false;
  auto w = std::make_unique<hapticd_msg_World>();  // about 9 kB
  dds::set_text(w->engine, impl_->options.client_id);
  w->time_s = time_s;
  w->shape_count = static_cast<std::int32_t>(shapes.size());
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const WorldShape& in = shapes[k];
    hapticd_msg_WorldShape& out = w->shapes[k];
    dds::set_text(out.body, in.body.view());
    out.shape = static_cast<std::int32_t>(in.kind);
    for (int a = 0; a < 3; ++a) out.size[a] = in.size[a];
    for (int a = 0; a < 4; ++a) out.color[a] = in.color[a];
    dds::to_msg(in.pose, out.shape_pose);
  }
  std::lock_guard lock(impl_->world_mutex);
  w->serial = ++impl_->world_serial;
  if (!impl_->world_writer_made) {
    impl_->world_writer_made = true;
    try {
      impl_->world_writer = std::make_unique<dds::Writer<hapticd_msg_World>>(impl_->participant);
    } catch (const std::exception&) {  // not permitted (DDS Security): publishing fails from now on
    }
  }
  return impl_->world_writer != nullptr && impl_->world_writer->write(*w);
}

bool Client::send_group(std::string_view group, std::span<const DeviceCommand> commands) {
  if (commands.size() > static_cast<std::size_t>(kMaxGroupDevices)) return false;
  auto g = std::make_unique<hapticd_msg_GroupCommand>();  // about 5 kB
  dds::set_text(g->group, group);
  g->command_count = static_cast<std::int32_t>(commands.size());
  for (std::size_t k = 0; k < commands.size(); ++k) {
    wire::to_msg(commands[k].command, commands[k].device, g->commands[k]);
    dds::set_text(g->commands[k].engine, impl_->options.client_id);
    g->commands[k].serial = impl_->serial.fetch_add(1) + 1;
  }
  dds::Writer<hapticd_msg_GroupCommand>* writer = impl_->group_command_writer(group);
  return writer != nullptr && writer->write(*g);
}

bool Client::send_coupling(std::string_view device, const Pose& proxy, const Twist& proxy_twist,
                           std::uint64_t state_serial) {
  return send(device, EngineCommand::coupling(proxy, proxy_twist, state_serial));
}

bool Client::send_wrench(std::string_view device, const Wrench& wrench, std::uint64_t state_serial) {
  return send(device, EngineCommand::force(wrench, state_serial));
}

bool Client::send_motion(std::string_view device, const Pose& pose, const Twist& twist, std::uint64_t state_serial) {
  return send(device, EngineCommand::motion(pose, twist, state_serial));
}

void Client::reset_serial() noexcept { impl_->serial.store(0); }

}  // namespace hapticd::client
