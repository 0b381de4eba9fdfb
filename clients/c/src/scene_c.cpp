// The C API of the session's haptic scene (hapticd/client.h, "the session's haptic scene") over the C++ client
// library's SceneClient: each function checks its arguments, calls the library and turns its answer into a status.
#include <cmath>
#include <cstring>
#include <span>
#include <string>

#include "c_status.hpp"
#include "c_values.hpp"
#include "client_handle.hpp"
#include "hapticd/client.h"
#include "hapticd/client/client.hpp"

namespace {

using hapticd::client_c::fail;
using hapticd::client_c::from_c;
using hapticd::client_c::guarded;
using hapticd::client_c::name_of;
using hapticd::client_c::to_c;
using hapticd::client_c::valid_timeout;
namespace client = hapticd::client;

hapticd_status answer(const client::SceneReply& r, hapticd_reply* out) noexcept {
  if (out != nullptr) to_c(client::Reply{r.answered, r.accepted, r.message, {}}, *out);
  if (!r.answered) return fail(HAPTICD_ERROR_TIMEOUT, r.message);
  if (!r.accepted) return fail(HAPTICD_ERROR_REFUSED, r.message);
  return HAPTICD_OK;
}

// The common checks, then f(scene, timeout) with its answer as the status.
template <class F>
hapticd_status ask(hapticd_client* c, double timeout_s, hapticd_reply* reply, F&& f) noexcept {
  if (c == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client is NULL");
  if (!valid_timeout(timeout_s)) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the timeout must be finite and >= 0");
  return guarded([&] { return answer(f(c->client.scene(), client::Timeout(timeout_s)), reply); });
}

hapticd_status bad_text(const char* what) noexcept {
  return fail(HAPTICD_ERROR_INVALID_ARGUMENT, std::string(what) + " is NULL or empty");
}

// A list's entries into out (up to capacity), their number into *count.
template <class T, class C>
hapticd_status listing(hapticd_client* c, C* out, int32_t capacity, int32_t* count, double timeout_s,
                       hapticd_reply* reply, client::SceneReply (client::SceneClient::*get)(client::Timeout),
                       std::vector<T> client::SceneReply::*entries) noexcept {
  if (count == nullptr || capacity < 0 || (capacity > 0 && out == nullptr))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "count or out is NULL (or capacity < 0)");
  *count = 0;
  return ask(c, timeout_s, reply, [&](client::SceneClient& s, client::Timeout t) {
    client::SceneReply r = (s.*get)(t);
    const std::vector<T>& list = r.*entries;
    *count = static_cast<int32_t>(list.size());
    for (std::size_t i = 0; i < list.size() && i < static_cast<std::size_t>(capacity); ++i) to_c(list[i], out[i]);
    return r;
  });
}

}  // namespace

extern "C" {

hapticd_status hapticd_client_scene_claim(hapticd_client* c, double timeout_s, hapticd_reply* reply) {
  return ask(c, timeout_s, reply, [](client::SceneClient& s, client::Timeout t) { return s.claim(t); });
}

hapticd_status hapticd_client_scene_release(hapticd_client* c, double timeout_s, hapticd_reply* reply) {
  return ask(c, timeout_s, reply, [](client::SceneClient& s, client::Timeout t) { return s.release(t); });
}

hapticd_status hapticd_client_scene_add(hapticd_client* c, const char* object, double timeout_s, hapticd_reply* reply) {
  if (object == nullptr || *object == '\0') return bad_text("the object");
  return ask(c, timeout_s, reply, [&](client::SceneClient& s, client::Timeout t) { return s.add(object, t); });
}

hapticd_status hapticd_client_scene_add_mesh(hapticd_client* c, const char* object, const double* vertices,
                                             int64_t vertex_count, const uint32_t* triangles, int64_t triangle_count,
                                             double timeout_s, hapticd_reply* reply) {
  if (object == nullptr || *object == '\0') return bad_text("the object");
  if (vertex_count < 0 || triangle_count < 0 || (vertex_count > 0 && vertices == nullptr) ||
      (triangle_count > 0 && triangles == nullptr))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "vertices or triangles are NULL (or a count < 0)");
  const std::span<const double> v(vertices, static_cast<std::size_t>(vertex_count) * 3);
  const std::span<const std::uint32_t> tr(triangles, static_cast<std::size_t>(triangle_count) * 3);
  return ask(c, timeout_s, reply,
             [&](client::SceneClient& s, client::Timeout t) { return s.add_mesh(object, v, tr, t); });
}

hapticd_status hapticd_client_scene_remove(hapticd_client* c, const char* object, double timeout_s,
                                           hapticd_reply* reply) {
  const std::string_view name = name_of(object);
  if (name.empty()) return hapticd::client_c::bad_name("the object", object);
  return ask(c, timeout_s, reply, [&](client::SceneClient& s, client::Timeout t) { return s.remove(name, t); });
}

hapticd_status hapticd_client_scene_set_material(hapticd_client* c, const char* object, const char* material,
                                                 double timeout_s, hapticd_reply* reply) {
  const std::string_view name = name_of(object);
  if (name.empty()) return hapticd::client_c::bad_name("the object", object);
  if (material == nullptr || *material == '\0') return bad_text("the material");
  return ask(c, timeout_s, reply,
             [&](client::SceneClient& s, client::Timeout t) { return s.set_material(name, material, t); });
}

hapticd_status hapticd_client_scene_move(hapticd_client* c, const char* object, const hapticd_pose* pose) {
  if (c == nullptr || pose == nullptr) return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client or the pose is NULL");
  const std::string_view name = name_of(object);
  if (name.empty()) return hapticd::client_c::bad_name("the object", object);
  return guarded([&] {
    return c->client.scene().move(name, from_c(*pose)) ? HAPTICD_OK
                                                       : fail(HAPTICD_ERROR_INTERNAL, "cannot write the move");
  });
}

hapticd_status hapticd_client_scene_refused_moves(hapticd_client* c, uint64_t* count, char* last, int32_t capacity) {
  if (c == nullptr || count == nullptr || (last != nullptr && capacity <= 0))
    return fail(HAPTICD_ERROR_INVALID_ARGUMENT, "the client or count is NULL (or last without a capacity)");
  return guarded([&] {
    client::SceneClient& s = c->client.scene();
    *count = s.refused_moves();
    if (last != nullptr) {
      const std::string why = s.last_refusal();
      const std::size_t n = std::min(why.size(), static_cast<std::size_t>(capacity) - 1);
      std::memcpy(last, why.data(), n);
      last[n] = '\0';
    }
    return HAPTICD_OK;
  });
}

hapticd_status hapticd_client_scene_objects(hapticd_client* c, hapticd_scene_object* out, int32_t capacity,
                                            int32_t* count, double timeout_s, hapticd_reply* reply) {
  return listing(c, out, capacity, count, timeout_s, reply, &client::SceneClient::objects,
                 &client::SceneReply::objects);
}

hapticd_status hapticd_client_scene_contacts(hapticd_client* c, hapticd_scene_contact* out, int32_t capacity,
                                             int32_t* count, double timeout_s, hapticd_reply* reply) {
  return listing(c, out, capacity, count, timeout_s, reply, &client::SceneClient::contacts,
                 &client::SceneReply::contacts);
}

}  // extern "C"
