#pragma once
// The haptic scene's DDS door (docs/haptic-scene.md, "Engines edit the scene"; docs/dds-interface.md, "The haptic
// scene"): the scene's requests (hapticd_scene_request) and a mesh's parts (hapticd_scene_mesh_part) are taken on a
// thread of this intake's own - an add builds its object there (a mesh of a million triangles takes seconds), so
// neither Cyclone's receive threads nor the gate's service thread (the devices' requests) ever wait for it - and
// handed to the gate's SceneGate, whose answers go out on hapticd_scene_reply.
//
// Who sent a request is the participant of its writer (PeerDirectory), as for the devices' requests; a claim's
// channel is its request writer, so the claim ends when that writer is gone (DdsDoor::channel_open). An object or a
// material comes as JSON only (checked here with JsonReader before the scene reads it: YAML's aliases could make a
// few kB of text into a deep tree). A request sent again with the same id is answered again and applied once (the
// last kRemembered answers are kept). An accepted move is not answered (one per object per frame).
#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <thread>

#include "doors/dds/peer_directory.hpp"
#include "gate/scene_gate.hpp"
#include "hapticd/dds/endpoints.hpp"
#include "hapticd/json_reader.hpp"
#include "hapticd_msg.h"

namespace hapticd::server {

class SceneIntake {
 public:
  static constexpr std::size_t kRemembered = 32;

  // Made only for a session with a scene (a server without one does not answer: see dds_door.cpp).
  SceneIntake(const dds::Participant& participant, SceneGate& scene, PeerDirectory& peers);
  ~SceneIntake();
  SceneIntake(const SceneIntake&) = delete;
  SceneIntake& operator=(const SceneIntake&) = delete;

  void start();
  void stop();  // joins the thread; idempotent

  // Whether `writer` (a claim's channel) is still matched on the scene's request reader.
  [[nodiscard]] bool channel_open(dds_instance_handle_t writer) const;
  [[nodiscard]] std::uint64_t answered() const noexcept { return answered_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t malformed() const noexcept { return malformed_.load(std::memory_order_relaxed); }

 private:
  void run();
  void take_requests();
  void take_parts();
  // The reply to `edit` from `peer` (a sample's participant), into reply_ (kept for a repeat unless it is a move).
  void answer(const SceneGate::Edit& edit, const std::optional<PeerId>& peer, dds_instance_handle_t writer,
              std::string_view client, std::uint64_t request_id, std::uint32_t first);
  void refuse(std::string_view client, std::uint64_t request_id, std::string_view why);
  // A repeat of a request answered before: its answer written again. True when it was one.
  bool repeat(const PeerId& peer, std::string_view client, std::uint64_t request_id);
  void remember(const PeerId& peer);

  SceneGate& scene_;
  PeerDirectory& peers_;
  dds::Reader<hapticd_msg_SceneRequest> requests_;
  dds::Reader<hapticd_msg_SceneMeshPart> parts_;
  dds::Writer<hapticd_msg_SceneReply> replies_;
  dds::Entity waitset_, wake_;
  JsonReader json_;
  std::string text_;                               // the edit's text, when made here (a material's name, quoted)
  std::unique_ptr<hapticd_msg_SceneReply> reply_;  // the one being written (about 10 kB: not on the stack)
  struct Answered {
    PeerId peer;
    std::unique_ptr<hapticd_msg_SceneReply> reply;  // carries the client id and the request id
  };
  std::deque<Answered> answers_;  // the newest kRemembered, the oldest first
  std::thread thread_;
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> answered_{0}, malformed_{0};
};

}  // namespace hapticd::server
