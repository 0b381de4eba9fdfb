#include "doors/dds/dds_door.hpp"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <optional>

#include "doors/dds/cyclone_log.hpp"
#include "hapticd/dds/conversion.hpp"
#include "session/device_requests.hpp"

namespace hapticd::server {
namespace {

// Sets the calling thread's CPUs; returns the previous set (to restore), nullopt if none were given.
std::optional<cpu_set_t> set_cpus(const std::vector<int>& cpus) {
  if (cpus.empty()) return std::nullopt;
  cpu_set_t previous;
  if (pthread_getaffinity_np(pthread_self(), sizeof previous, &previous) != 0) return std::nullopt;
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c : cpus) CPU_SET(c, &set);
  if (pthread_setaffinity_np(pthread_self(), sizeof set, &set) != 0) return std::nullopt;
  return previous;
}

}  // namespace

DdsDoor::DdsDoor(const DdsSettings& settings, Gate& gate, const std::vector<int>& cpus)
    : gate_(gate),
      command_filter_{DDS_TOPIC_FILTER_SAMPLE_ARG, {.sample_arg = &DdsDoor::command_for_us}, this},
      request_filter_{DDS_TOPIC_FILTER_SAMPLE_ARG, {.sample_arg = &DdsDoor::request_for_us}, this},
      group_command_filter_{DDS_TOPIC_FILTER_SAMPLE_ARG, {.sample_arg = &DdsDoor::group_command_for_us}, this},
      next_log_report_(std::chrono::steady_clock::now() + std::chrono::seconds(10)) {
  const DeviceGates& devices = gate.devices();
  double deadline = 1.0;
  for (const auto& d : devices) deadline = std::min(deadline, d->device->chain().engine_deadline_s);
  cyclone_log::route_to_logger(settings.log_lines_per_s, 20.0);  // before Cyclone has anything to say
  const std::optional<cpu_set_t> previous = set_cpus(cpus);
  std::vector<std::string> partitions = {"", dds::target_partition("*")};  // the default one, and every device's
  for (const auto& d : devices) partitions.push_back(dds::target_partition(d->device->name()));
  for (const GroupGate& g : devices.groups()) partitions.push_back(dds::target_partition(g.name));
  dds_ = std::make_unique<DdsEndpoints>(settings, dds::CommandTiming{deadline, 0.5}, command_filter_, request_filter_,
                                        group_command_filter_, partitions);
  if (previous) (void)pthread_setaffinity_np(pthread_self(), sizeof *previous, &*previous);
  intake_ = std::make_unique<CommandIntake>(*dds_, gate_);
  // The haptic scene's topics only where the session has a scene: a server without one stays silent, so an engine
  // on a domain shared with other servers hears only the server whose scene it edits.
  if (gate_.scene() != nullptr) scene_ = std::make_unique<SceneIntake>(dds_->participant, *gate_.scene(), dds_->peers);
}

DdsDoor::~DdsDoor() {
  intake_->close();
  scene_.reset();
  worlds_.reset();
}

void DdsDoor::relay_worlds(std::function<void(const hapticd_msg_World&)> sink) {
  worlds_ = std::make_unique<WorldRelay>(dds_->participant, std::move(sink));
}

void DdsDoor::start() {
  intake_->listen();
  if (scene_) scene_->start();
}

void DdsDoor::stop() {
  intake_->close();
  if (scene_) scene_->stop();
  cyclone_log::report_suppressed();
}

bool DdsDoor::channel_open(const Sender& s) const {
  // A device's claim is bound to a request writer, the scene's to a scene request writer.
  return s.peer.door == DoorKind::dds &&
         (dds_->peers.matched(dds_->request.get(), s.channel) || (scene_ && scene_->channel_open(s.channel)));
}

bool DdsDoor::alive(const PeerId& p) {
  return dds_->peers.has_live_writer(dds_->command.get(), p) ||
         dds_->peers.has_live_writer(dds_->group_command.get(), p);
}

void DdsDoor::answer_requests(RequestDispatcher& dispatcher) {
  dds_->request.take([&](const hapticd_msg_ControlRequest& m, const dds_sample_info_t& info) {
    // A device, a group or "*" (every device) of this server: the reader's filter keeps the rest out.
    if (!gate_.devices().request_target(dds::text_of(m.device))) return;
    const std::optional<PeerId> peer = dds_->peers.participant_of(dds_->request.get(), info.publication_handle);
    const std::optional<Sender> sender =
        peer ? std::optional<Sender>(Sender{*peer, info.publication_handle}) : std::nullopt;
    // One instance per device (the reply's key): no state kept per client id beyond the bounded AnsweredRequests.
    (void)dds_->reply.write(dispatcher.answer(m, sender));
  });
}

void DdsDoor::service() {
  intake_->count_deadline_misses();
  if (const auto now = std::chrono::steady_clock::now(); now >= next_log_report_) {
    cyclone_log::report_suppressed();
    next_log_report_ = now + std::chrono::seconds(10);
  }
}

void DdsDoor::state(std::size_t, const DeviceSnapshot&, const hapticd_msg_DeviceState& m) {
  (void)dds_->state.write(m);
}
void DdsDoor::repeat_state(const hapticd_msg_DeviceState& m) { (void)dds_->state.write(m); }
void DdsDoor::group_state(const hapticd_msg_GroupState& m, bool) { (void)dds_->group_state.write(m); }
void DdsDoor::description(const hapticd_msg_DeviceDescription& m) { (void)dds_->description.write(m); }
void DdsDoor::group_description(const hapticd_msg_GroupDescription& m) { (void)dds_->group_description.write(m); }
void DdsDoor::fault_report(const hapticd_msg_FaultReport& m) { (void)dds_->fault_report.write(m); }
void DdsDoor::event(const hapticd_msg_Event& m) { (void)dds_->event.write(m); }

void DdsDoor::telemetry(const hapticd_msg_Telemetry& m) {
  hapticd_msg_Telemetry t = m;
  if (const DeviceGate* d = gate_.devices().find(dds::text_of(m.device))) t.deadline_misses = deadline_misses(d->index);
  (void)dds_->telemetry.write(t);
}

bool DdsDoor::group_command_for_us(const void* sample, void* self) {
  DeviceGates& devices = static_cast<DdsDoor*>(self)->gate_.devices();
  if (devices.find_group(dds::text_of(static_cast<const hapticd_msg_GroupCommand*>(sample)->group)) != nullptr)
    return true;
  devices.count_unknown_command();
  return false;
}

bool DdsDoor::command_for_us(const void* sample, void* self) {
  DeviceGates& devices = static_cast<DdsDoor*>(self)->gate_.devices();
  if (devices.find(dds::text_of(static_cast<const hapticd_msg_EngineCommand*>(sample)->device)) != nullptr) return true;
  devices.count_unknown_command();  // malformed (the IDL's reason 0)
  return false;
}

bool DdsDoor::request_for_us(const void* sample, void* self) {
  DeviceGates& devices = static_cast<DdsDoor*>(self)->gate_.devices();
  // A device, a group ("*" for group requests: every device of every server) of this server.
  if (devices.request_target(dds::text_of(static_cast<const hapticd_msg_ControlRequest*>(sample)->device))) return true;
  devices.count_unknown_request();
  return false;
}

}  // namespace hapticd::server
