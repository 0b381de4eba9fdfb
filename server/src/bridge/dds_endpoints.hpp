#pragma once
// The server's DDS entities: one participant, a writer per published topic, the command and request readers
// (with the device filters), the receiver's waitset and wake-up, and the directory of who wrote what. The command
// and request readers read the default partition and the partition of each of the server's devices and groups
// (dds::target_partition): a client writes a device's requests and commands in its partition, so that DDS
// Security's permissions can grant an identity some devices and not others.
#include "bridge/peer_directory.hpp"
#include "config/session_config.hpp"
#include "hapticd/dds/endpoints.hpp"
#include "hapticd_msg.h"

namespace hapticd::server {

struct DdsEndpoints {
  DdsEndpoints(const DdsSettings& s, const dds::CommandTiming& timing, const dds_topic_filter& command_filter,
               const dds_topic_filter& request_filter, const dds_topic_filter& group_command_filter,
               const std::vector<std::string>& partitions)
      : participant(dds::ParticipantOptions{s.domain_id, s.cyclone_config, s.network}),
        description(participant),
        state(participant),
        event(participant),
        telemetry(participant),
        fault_report(participant),
        reply(participant),
        group_description(participant),
        group_state(participant),
        command(participant, timing, &command_filter, partitions),
        request(participant, {}, &request_filter, partitions),
        group_command(participant, timing, &group_command_filter, partitions),
        waitset(dds::check(dds_create_waitset(participant.get()), "cannot create a DDS waitset")),
        wake(dds::check(dds_create_guardcondition(participant.get()), "cannot create a DDS guard condition")),
        peers(static_cast<std::size_t>(s.max_peers)) {}

  dds::Participant participant;
  dds::Writer<hapticd_msg_DeviceDescription> description;
  dds::Writer<hapticd_msg_DeviceState> state;
  dds::Writer<hapticd_msg_Event> event;
  dds::Writer<hapticd_msg_Telemetry> telemetry;
  dds::Writer<hapticd_msg_FaultReport> fault_report;
  dds::Writer<hapticd_msg_ControlReply> reply;
  dds::Writer<hapticd_msg_GroupDescription> group_description;
  dds::Writer<hapticd_msg_GroupState> group_state;
  dds::Reader<hapticd_msg_EngineCommand> command;
  dds::Reader<hapticd_msg_ControlRequest> request;
  dds::Reader<hapticd_msg_GroupCommand> group_command;
  dds::Entity waitset;  // the receiver: requests and the wake-up
  dds::Entity wake;
  PeerDirectory peers;  // who wrote a command or request: the writer's participant
};

}  // namespace hapticd::server
