#include "doors/dds/scene_intake.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <vector>

#include "executor/loop_clock.hpp"
#include "hapticd/dds/conversion.hpp"

namespace hapticd::server {
namespace {

std::optional<SceneGate::Op> op_of(hapticd_msg_SceneOp op) {
  switch (op) {
    case hapticd_msg_SCENE_CLAIM:
      return SceneGate::Op::claim;
    case hapticd_msg_SCENE_RELEASE:
      return SceneGate::Op::release;
    case hapticd_msg_SCENE_ADD:
      return SceneGate::Op::add;
    case hapticd_msg_SCENE_REMOVE:
      return SceneGate::Op::remove;
    case hapticd_msg_SCENE_MATERIAL:
      return SceneGate::Op::material;
    case hapticd_msg_SCENE_MOVE:
      return SceneGate::Op::move;
    case hapticd_msg_SCENE_LIST:
      return SceneGate::Op::list;
    case hapticd_msg_SCENE_CONTACTS:
      return SceneGate::Op::contacts;
  }
  return std::nullopt;
}

bool plain_name(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.';
  });
}

void put(const Eigen::Vector3d& v, double (&out)[3]) {
  for (int i = 0; i < 3; ++i) out[i] = v[i];
}

// The page of `list` from `first` into `entries` (at most MAX_SCENE_ENTRIES, each by `fill`), its place in the
// list into the reply; returns how many.
template <class T, class Entry, std::size_t N, class Fill>
std::int32_t page(const std::vector<T>& list, std::uint32_t first, hapticd_msg_SceneReply& out, Entry (&entries)[N],
                  Fill&& fill) {
  const std::size_t total = list.size(), from = std::min<std::size_t>(first, total);
  const std::size_t n = std::min(N, total - from);
  out.total = static_cast<std::uint32_t>(total);
  out.first = static_cast<std::uint32_t>(from);
  for (std::size_t i = 0; i < n; ++i) fill(list[from + i], entries[i]);
  return static_cast<std::int32_t>(n);
}

}  // namespace

SceneIntake::SceneIntake(const dds::Participant& participant, SceneGate& scene, PeerDirectory& peers)
    : scene_(scene),
      peers_(peers),
      requests_(participant),
      parts_(participant),
      replies_(participant),
      waitset_(dds::check(dds_create_waitset(participant.get()), "cannot create a DDS waitset")),
      wake_(dds::check(dds_create_guardcondition(participant.get()), "cannot create a DDS guard condition")),
      reply_(std::make_unique<hapticd_msg_SceneReply>()) {
  for (dds_entity_t r : {requests_.get(), parts_.get()}) {
    dds::check(dds_set_status_mask(r, DDS_DATA_AVAILABLE_STATUS), "cannot set a DDS status mask");
    dds::check(dds_waitset_attach(waitset_.get(), r, r), "cannot attach a DDS reader to a waitset");
  }
  dds::check(dds_waitset_attach(waitset_.get(), wake_.get(), wake_.get()), "cannot attach a DDS guard condition");
}

SceneIntake::~SceneIntake() { stop(); }

void SceneIntake::start() {
  if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
}

void SceneIntake::stop() {
  stopping_.store(true);
  (void)dds_set_guardcondition(wake_.get(), true);
  if (thread_.joinable()) thread_.join();
}

bool SceneIntake::channel_open(dds_instance_handle_t writer) const { return peers_.matched(requests_.get(), writer); }

void SceneIntake::run() {
  std::array<dds_attach_t, 4> triggered{};
  while (!stopping_.load()) {
    (void)dds_waitset_wait(waitset_.get(), triggered.data(), triggered.size(), DDS_MSECS(200));
    // Parts first: an engine waits for its last part's answer before it adds the mesh.
    take_parts();
    take_requests();
  }
}

void SceneIntake::take_requests() {
  requests_.take([&](const hapticd_msg_SceneRequest& m, const dds_sample_info_t& info) {
    const std::string_view client = dds::text_of(m.client);
    const std::optional<SceneGate::Op> op = op_of(m.op);
    if (!dds::valid_text(m.client) || !dds::valid_text(m.object_name) || !dds::valid_text(m.content) || !op) {
      malformed_.fetch_add(1, std::memory_order_relaxed);
      refuse(client, m.request_id, "malformed: a text not terminated or not UTF-8, or an unknown op");
      return;
    }
    const std::optional<PeerId> peer = peers_.participant_of(requests_.get(), info.publication_handle);
    if (peer && repeat(*peer, client, m.request_id)) return;
    SceneGate::Edit edit;
    edit.op = *op;
    edit.name = dds::text_of(m.object_name);
    edit.pose = dds::to_pose(m.placement);
    const std::string_view content = dds::text_of(m.content);
    if (edit.op == SceneGate::Op::add || edit.op == SceneGate::Op::material) {
      // JSON only: an object (the object, a material in place) or, for a material, a name (quoted or not).
      const bool parsed = json_.parse(content);
      const JsonReader::Kind kind = parsed ? json_.root().kind() : JsonReader::Kind::null;
      const JsonReader::Value upload = kind == JsonReader::Kind::object && edit.op == SceneGate::Op::add
                                           ? json_.root()["upload"]
                                           : JsonReader::Value();
      if (upload && !upload.string()) {
        malformed_.fetch_add(1, std::memory_order_relaxed);
        refuse(client, m.request_id, "content: an object's upload is the name of an upload");
        return;
      }
      if (kind == JsonReader::Kind::object ||
          (edit.op == SceneGate::Op::material && kind == JsonReader::Kind::string)) {
        edit.text = content;
        if (upload) edit.upload = *upload.string();  // a mesh made of a finished upload
      } else if (edit.op == SceneGate::Op::material && plain_name(content)) {
        text_ = "\"" + std::string(content) + "\"";
        edit.text = text_;
      } else {
        malformed_.fetch_add(1, std::memory_order_relaxed);
        refuse(client, m.request_id,
               edit.op == SceneGate::Op::add ? "content: the object must be a JSON object"
                                             : "content: the material must be a name or a JSON object");
        return;
      }
    }
    answer(edit, peer, info.publication_handle, client, m.request_id, m.first);
  });
}

void SceneIntake::take_parts() {
  parts_.take([&](const hapticd_msg_SceneMeshPart& m, const dds_sample_info_t& info) {
    const std::string_view client = dds::text_of(m.client);
    if (!dds::valid_text(m.client) || !dds::valid_text(m.upload) || m.vertex_count < 0 ||
        m.vertex_count > hapticd_msg_MAX_PART_VERTICES || m.triangle_count < 0 ||
        m.triangle_count > hapticd_msg_MAX_PART_TRIANGLES) {
      malformed_.fetch_add(1, std::memory_order_relaxed);
      refuse(client, m.request_id, "malformed: a text not terminated or not UTF-8, or a count out of its bounds");
      return;
    }
    const std::optional<PeerId> peer = peers_.participant_of(parts_.get(), info.publication_handle);
    if (peer && repeat(*peer, client, m.request_id)) return;
    SceneGate::Edit edit;
    edit.op = SceneGate::Op::upload;
    edit.upload = dds::text_of(m.upload);
    edit.part = m.part;
    edit.parts = m.parts;
    edit.vertices = std::span<const double>(m.vertices, static_cast<std::size_t>(m.vertex_count) * 3);
    edit.triangles = std::span<const std::uint32_t>(m.triangles, static_cast<std::size_t>(m.triangle_count) * 3);
    answer(edit, peer, info.publication_handle, client, m.request_id, 0);
  });
}

void SceneIntake::answer(const SceneGate::Edit& edit, const std::optional<PeerId>& peer, dds_instance_handle_t writer,
                         std::string_view client, std::uint64_t request_id, std::uint32_t first) {
  if (!peer) {  // not (or no longer) matched: discovery has not told us the writer yet; the client sends it again
    refuse(client, request_id, "the requester is not known yet (discovery): send the request again");
    return;
  }
  const SceneGate::Reply r = scene_.apply(edit, Sender{*peer, writer}, client, monotonic_now_ns());
  if (r.accepted && edit.op == SceneGate::Op::move) return;
  hapticd_msg_SceneReply& out = *reply_;
  out = hapticd_msg_SceneReply{};
  dds::set_text(out.client, client);
  out.request_id = request_id;
  out.accepted = r.accepted;
  dds::set_text(out.message, r.message);
  if (r.objects)
    out.object_count = page(*r.objects, first, out, out.objects, [](const SceneObjectSummary& o, auto& e) {
      dds::set_text(e.object_name, o.name);
      dds::set_text(e.shape, o.shape);
      e.uid = o.uid;
      e.moving = o.moving;
      e.triangle_count = o.triangles;
      dds::to_msg(o.pose, e.placement);
    });
  if (r.contacts)
    out.contact_count = page(*r.contacts, first, out, out.contacts, [](const SceneContact& c, auto& e) {
      dds::set_text(e.device, c.device);
      dds::set_text(e.object_name, c.object);
      put(c.force, e.force);
      put(c.torque, e.torque);
      put(c.point, e.point);
    });
  (void)replies_.write(out);
  answered_.fetch_add(1, std::memory_order_relaxed);
  // Questions are answered anew each time, and a move is never sent again; an edit's answer is kept, so that its
  // repeat is not applied again.
  if (edit.op != SceneGate::Op::list && edit.op != SceneGate::Op::contacts && edit.op != SceneGate::Op::move)
    remember(*peer);
}

void SceneIntake::refuse(std::string_view client, std::uint64_t request_id, std::string_view why) {
  hapticd_msg_SceneReply& out = *reply_;
  out = hapticd_msg_SceneReply{};
  dds::set_text(out.client, client);
  out.request_id = request_id;
  dds::set_text(out.message, why);
  (void)replies_.write(out);
}

bool SceneIntake::repeat(const PeerId& peer, std::string_view client, std::uint64_t request_id) {
  for (const Answered& a : answers_)
    if (a.peer == peer && a.reply->request_id == request_id && dds::text_of(a.reply->client) == client) {
      (void)replies_.write(*a.reply);
      return true;
    }
  return false;
}

void SceneIntake::remember(const PeerId& peer) {
  if (answers_.size() == kRemembered) answers_.pop_front();
  answers_.push_back({peer, std::make_unique<hapticd_msg_SceneReply>(*reply_)});
}

}  // namespace hapticd::server
