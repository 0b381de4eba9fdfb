#pragma once
// The DDS door's entities: one participant, a writer per published topic, the command and request readers
// (with the device filters), and the directory of who wrote what. The command
// and request readers read the default partition and the partition of each of the server's devices and groups
// (dds::target_partition): a client writes a device's requests and commands in its partition, so that DDS
// Security's permissions can grant an identity some devices and not others.
#include "config/session_config.hpp"
#include "doors/dds/peer_directory.hpp"
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
  PeerDirectory peers;  // who wrote a command or request: the writer's participant
};

}  // namespace hapticd::server
