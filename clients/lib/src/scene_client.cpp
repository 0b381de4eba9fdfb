#include "hapticd/client/scene_client.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <thread>

#include "hapticd/dds/conversion.hpp"
#include "hapticd/dds/endpoints.hpp"
#include "request_timing.hpp"
#include "scene_wire.hpp"

namespace hapticd::client {
namespace {
// Only a server whose session has a scene answers (the others on the domain stay silent).
constexpr const char* kNoAnswer =
    "no answer within the timeout: no server on this DDS domain has a haptic scene (a session file with a `scene` "
    "section), or it is not reachable";
constexpr std::uint64_t kMoveBit = std::uint64_t{1} << 63;  // a move's id: its refusal is told apart from the rest

SceneReply unanswered(std::string why) {
  SceneReply r;
  r.message = std::move(why);
  return r;
}
}  // namespace

struct SceneClient::Impl {
  Impl(const dds::Participant& participant, std::string id)
      : client_id(std::move(id)), requests(participant), parts(participant), replies(participant) {
    const dds::Listener listener(dds_create_listener(this));
    dds_lset_data_available(listener.get(), [](dds_entity_t, void* self) { static_cast<Impl*>(self)->take(); });
    replies.set_listener(listener.get());  // last: it may run at once
  }
  ~Impl() {
    (void)dds_set_listener(replies.get(), nullptr);
    std::lock_guard take_done(take_mutex);
  }

  // Cyclone's receive thread: the answers to this client's requests.
  void take() {
    std::lock_guard one_at_a_time(take_mutex);
    replies.take([&](const hapticd_msg_SceneReply& r, const dds_sample_info_t&) {
      if (dds::text_of(r.client) != client_id) return;
      {
        std::lock_guard lock(mutex);
        if ((r.request_id & kMoveBit) != 0) {
          if (!r.accepted) {
            ++refused_moves;
            last_refusal = std::string(dds::text_of(r.message));
          }
          return;
        }
        if (!pending.contains(r.request_id)) return;  // another copy's answer, taken already
        answers[r.request_id] = std::make_unique<hapticd_msg_SceneReply>(r);
      }
      changed.notify_all();
    });
  }

  // Writes m (its request_id set here) until it is answered or the timeout passes; the answer or nothing.
  template <class Msg>
  std::unique_ptr<hapticd_msg_SceneReply> ask(const dds::Writer<Msg>& writer, Msg& m, Timeout timeout) {
    const auto until = std::chrono::steady_clock::now() + countable(timeout);
    m.request_id = next_id.fetch_add(1) & ~kMoveBit;
    // A reliable writer delivers to the readers it has matched: give discovery a moment.
    while (writer.matched() == 0 && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::unique_lock lock(mutex);
    pending.insert(m.request_id);
    const auto answered = [&] { return answers.contains(m.request_id); };
    for (;;) {
      lock.unlock();
      const bool written = writer.write(m);
      lock.lock();
      if (!written && !answered()) break;
      const auto retry = std::min(until, std::chrono::steady_clock::now() + kRequestRetry);
      if (changed.wait_until(lock, retry, answered) || retry >= until) break;
    }
    pending.erase(m.request_id);
    auto found = answers.find(m.request_id);
    if (found == answers.end()) return nullptr;
    std::unique_ptr<hapticd_msg_SceneReply> answer = std::move(found->second);
    answers.erase(found);
    return answer;
  }

  SceneReply request(hapticd_msg_SceneOp op, std::string_view object, std::string_view content, Timeout timeout,
                     std::uint32_t first = 0, std::unique_ptr<hapticd_msg_SceneReply>* raw = nullptr) {
    if (content.size() > hapticd_msg_SCENE_TEXT_SIZE)
      return unanswered("not sent: the text is longer than " + std::to_string(hapticd_msg_SCENE_TEXT_SIZE) + " bytes");
    if (object.size() > 31) return unanswered("not sent: an object's name is at most 31 characters");
    auto m = std::make_unique<hapticd_msg_SceneRequest>();
    dds::set_text(m->client, client_id);
    m->op = op;
    dds::set_text(m->object_name, object);
    dds::set_text(m->content, content);
    m->first = first;
    std::unique_ptr<hapticd_msg_SceneReply> answer = ask(requests, *m, timeout);
    if (!answer) return unanswered(kNoAnswer);
    SceneReply r = scene_wire::from_msg(*answer);
    if (raw != nullptr) *raw = std::move(answer);
    return r;
  }

  // Every page of a list or contacts answer.
  SceneReply gather(hapticd_msg_SceneOp op, Timeout timeout) {
    SceneReply all;
    std::uint32_t first = 0;
    for (;;) {
      std::unique_ptr<hapticd_msg_SceneReply> raw;
      SceneReply page = request(op, {}, {}, timeout, first, &raw);
      if (!page.accepted) return page;
      all.answered = all.accepted = true;
      all.message = page.message;
      all.objects.insert(all.objects.end(), page.objects.begin(), page.objects.end());
      all.contacts.insert(all.contacts.end(), page.contacts.begin(), page.contacts.end());
      const std::uint32_t count = static_cast<std::uint32_t>(std::max(raw->object_count, raw->contact_count));
      first = raw->first + count;
      if (count == 0 || first >= raw->total) return all;
    }
  }

  std::string client_id;
  dds::Writer<hapticd_msg_SceneRequest> requests;
  dds::Writer<hapticd_msg_SceneMeshPart> parts;
  std::mutex take_mutex;
  std::mutex mutex;
  std::condition_variable changed;
  std::set<std::uint64_t> pending;
  std::map<std::uint64_t, std::unique_ptr<hapticd_msg_SceneReply>> answers;
  std::uint64_t refused_moves = 0;
  std::string last_refusal;
  // Ids start at a random point: answers are matched by (client id, request id).
  std::atomic<std::uint64_t> next_id{std::random_device{}() | (std::uint64_t{std::random_device{}()} << 32) | 1};
  std::atomic<std::uint64_t> next_upload{1};
  dds::Reader<hapticd_msg_SceneReply> replies;  // last: its listener may run once it is set
};

SceneClient::SceneClient(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SceneClient::~SceneClient() = default;

std::unique_ptr<SceneClient> make_scene_client(const dds::Participant& participant, std::string client_id) {
  return std::make_unique<SceneClient>(std::make_unique<SceneClient::Impl>(participant, std::move(client_id)));
}

SceneReply SceneClient::claim(Timeout timeout) { return impl_->request(hapticd_msg_SCENE_CLAIM, {}, {}, timeout); }
SceneReply SceneClient::release(Timeout timeout) { return impl_->request(hapticd_msg_SCENE_RELEASE, {}, {}, timeout); }
SceneReply SceneClient::add(std::string_view object, Timeout timeout) {
  return impl_->request(hapticd_msg_SCENE_ADD, {}, object, timeout);
}
SceneReply SceneClient::remove(std::string_view object, Timeout timeout) {
  return impl_->request(hapticd_msg_SCENE_REMOVE, object, {}, timeout);
}
SceneReply SceneClient::set_material(std::string_view object, std::string_view material, Timeout timeout) {
  return impl_->request(hapticd_msg_SCENE_MATERIAL, object, material, timeout);
}
SceneReply SceneClient::objects(Timeout timeout) { return impl_->gather(hapticd_msg_SCENE_LIST, timeout); }
SceneReply SceneClient::contacts(Timeout timeout) { return impl_->gather(hapticd_msg_SCENE_CONTACTS, timeout); }

bool SceneClient::move(std::string_view object, const Pose& pose) {
  if (object.size() > 31) return false;
  hapticd_msg_SceneRequest m{};
  dds::set_text(m.client, impl_->client_id);
  m.request_id = impl_->next_id.fetch_add(1) | kMoveBit;
  m.op = hapticd_msg_SCENE_MOVE;
  dds::set_text(m.object_name, object);
  dds::to_msg(pose, m.placement);
  return impl_->requests.write(m);
}

SceneReply SceneClient::add_mesh(std::string_view object, std::span<const double> vertices,
                                 std::span<const std::uint32_t> triangles, Timeout timeout) {
  if (vertices.size() % 3 != 0 || triangles.size() % 3 != 0)
    return unanswered("not sent: vertices and triangles come three numbers each");
  // The object names its upload in place of a file: {"upload": "<name>", ...the object's members}.
  const std::size_t open = object.find('{');
  if (open == std::string_view::npos) return unanswered("not sent: the object must be a JSON object");
  const std::string upload = "mesh-" + std::to_string(impl_->next_upload.fetch_add(1));
  const std::size_t rest = object.find_first_not_of(" \t\r\n", open + 1);
  const bool empty = rest != std::string_view::npos && object[rest] == '}';
  const std::string text = std::string(object.substr(0, open + 1)) + "\"upload\": \"" + upload + "\"" +
                           (empty ? "" : ", ") + std::string(object.substr(open + 1));

  const std::size_t nv = vertices.size() / 3, nt = triangles.size() / 3;
  const std::size_t count = std::max<std::size_t>(
      1, std::max((nv + kPartVertices - 1) / kPartVertices, (nt + kPartTriangles - 1) / kPartTriangles));
  auto part = std::make_unique<hapticd_msg_SceneMeshPart>();
  for (std::size_t k = 0; k < count; ++k) {
    *part = hapticd_msg_SceneMeshPart{};
    dds::set_text(part->client, impl_->client_id);
    dds::set_text(part->upload, upload);
    part->part = static_cast<std::int32_t>(k);
    part->parts = static_cast<std::int32_t>(count);
    const std::size_t v0 = std::min(nv, k * kPartVertices), v1 = std::min(nv, v0 + kPartVertices);
    const std::size_t t0 = std::min(nt, k * kPartTriangles), t1 = std::min(nt, t0 + kPartTriangles);
    part->vertex_count = static_cast<std::int32_t>(v1 - v0);
    part->triangle_count = static_cast<std::int32_t>(t1 - t0);
    std::copy(vertices.begin() + static_cast<std::ptrdiff_t>(3 * v0),
              vertices.begin() + static_cast<std::ptrdiff_t>(3 * v1), part->vertices);
    std::copy(triangles.begin() + static_cast<std::ptrdiff_t>(3 * t0),
              triangles.begin() + static_cast<std::ptrdiff_t>(3 * t1), part->triangles);
    std::unique_ptr<hapticd_msg_SceneReply> answer = impl_->ask(impl_->parts, *part, timeout);
    if (!answer) return unanswered(std::string(kNoAnswer) + " (the upload's part " + std::to_string(k) + ")");
    if (!answer->accepted) return scene_wire::from_msg(*answer);
  }
  return impl_->request(hapticd_msg_SCENE_ADD, {}, text, timeout);
}

std::uint64_t SceneClient::refused_moves() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->refused_moves;
}

std::string SceneClient::last_refusal() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->last_refusal;
}

}  // namespace hapticd::client
