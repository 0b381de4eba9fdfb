#pragma once
// hapticd's topics: name, type and quality of service of each (docs/dds-interface.md has the table and why).
#include <memory>

#include "hapticd/dds/entity.hpp"
#include "hapticd_msg.h"

namespace hapticd::dds {

enum class TopicKind { description, state, command, request, reply, event, telemetry, fault_report, link };

template <class T>
struct TopicOf;
#define HAPTICD_DDS_TOPIC(TYPE, KIND, NAME)                                             \
  template <>                                                                           \
  struct TopicOf<TYPE> {                                                                \
    static constexpr TopicKind kind = TopicKind::KIND;                                  \
    static constexpr const char* name = NAME;                                           \
    static const dds_topic_descriptor_t* descriptor() noexcept { return &TYPE##_desc; } \
  };
HAPTICD_DDS_TOPIC(hapticd_msg_DeviceDescription, description, "hapticd_description")
HAPTICD_DDS_TOPIC(hapticd_msg_DeviceState, state, "hapticd_state")
HAPTICD_DDS_TOPIC(hapticd_msg_EngineCommand, command, "hapticd_command")
HAPTICD_DDS_TOPIC(hapticd_msg_ControlRequest, request, "hapticd_request")
HAPTICD_DDS_TOPIC(hapticd_msg_ControlReply, reply, "hapticd_reply")
HAPTICD_DDS_TOPIC(hapticd_msg_Event, event, "hapticd_event")
HAPTICD_DDS_TOPIC(hapticd_msg_Telemetry, telemetry, "hapticd_telemetry")
HAPTICD_DDS_TOPIC(hapticd_msg_FaultReport, fault_report, "hapticd_fault_report")
HAPTICD_DDS_TOPIC(hapticd_msg_GroupDescription, description, "hapticd_group_description")
HAPTICD_DDS_TOPIC(hapticd_msg_GroupState, state, "hapticd_group_state")
HAPTICD_DDS_TOPIC(hapticd_msg_GroupCommand, command, "hapticd_group_command")
HAPTICD_DDS_TOPIC(hapticd_msg_World, state, "hapticd_world")
HAPTICD_DDS_TOPIC(hapticd_msg_TeleopPacket, link, "hapticd_teleop")
HAPTICD_DDS_TOPIC(hapticd_msg_SceneRequest, request, "hapticd_scene_request")
HAPTICD_DDS_TOPIC(hapticd_msg_SceneMeshPart, request, "hapticd_scene_mesh_part")
HAPTICD_DDS_TOPIC(hapticd_msg_SceneReply, reply, "hapticd_scene_reply")
#undef HAPTICD_DDS_TOPIC

struct QosDeleter {
  void operator()(dds_qos_t* q) const noexcept { dds_delete_qos(q); }
};
using Qos = std::unique_ptr<dds_qos_t, QosDeleter>;

// Engine commands: how often a writer must write (deadline) and how soon a dead writer is noticed
// (liveliness lease). Readers request these; writers offer them (a writer offering less does not match).
struct CommandTiming {
  double deadline_s = 0.05;
  double liveliness_lease_s = 0.5;
};

// The QoS of a topic; readers request what writers offer, so both sides use the same.
[[nodiscard]] Qos topic_qos(TopicKind kind, const CommandTiming& timing = {});

}  // namespace hapticd::dds
