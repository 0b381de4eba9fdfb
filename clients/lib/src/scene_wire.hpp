#pragma once
// The scene's answers from the wire, and the SceneClient a Client makes (private to the client library).
#include <algorithm>
#include <memory>
#include <string>

#include "hapticd/client/scene_client.hpp"
#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/participant.hpp"
#include "hapticd_msg.h"

namespace hapticd::client {

std::unique_ptr<SceneClient> make_scene_client(const dds::Participant& participant, std::string client_id);

namespace scene_wire {

inline SceneReply from_msg(const hapticd_msg_SceneReply& m) {
  const auto v = [](const double(&a)[3]) { return Eigen::Vector3d(a[0], a[1], a[2]); };
  SceneReply r;
  r.answered = true;
  r.accepted = m.accepted;
  r.message = std::string(dds::text_of(m.message));
  const int objects = std::clamp<std::int32_t>(m.object_count, 0, hapticd_msg_MAX_SCENE_ENTRIES);
  for (int i = 0; i < objects; ++i) {
    const hapticd_msg_SceneObjectEntry& e = m.objects[i];
    r.objects.push_back({std::string(dds::text_of(e.object_name)), std::string(dds::text_of(e.shape)), e.uid, e.moving,
                         e.triangle_count, dds::to_pose(e.placement)});
  }
  const int contacts = std::clamp<std::int32_t>(m.contact_count, 0, hapticd_msg_MAX_SCENE_ENTRIES);
  for (int i = 0; i < contacts; ++i) {
    const hapticd_msg_SceneContactEntry& e = m.contacts[i];
    r.contacts.push_back({std::string(dds::text_of(e.device)), std::string(dds::text_of(e.object_name)), v(e.force),
                          v(e.torque), v(e.point)});
  }
  return r;
}

}  // namespace scene_wire
}  // namespace hapticd::client
