// The session's haptic scene over DDS (hapticd/client/scene_client.hpp) as hapticd.Scene, from Client.scene(). Every
// call that waits releases the GIL; a refused edit raises RequestRefused, no answer in time Timeout.
#include <pybind11/numpy.h>

#include <limits>
#include <vector>

#include "bindings.hpp"
#include "client_handle.hpp"
#include "convert.hpp"
#include "hapticd/client/scene_client.hpp"

namespace hapticd::python {

namespace {

using client::SceneClient;
using client::SceneReply;
using client::Timeout;

// Client.scene()'s object: the client it belongs to (kept alive by it; closed with it).
struct SceneHandle {
  ClientHandle* client;
  SceneClient& get() { return client->get().scene(); }
};

// An object or a material: a str as it is, anything else (a dict) as JSON.
std::string json_of(const py::object& value) {
  if (py::isinstance<py::str>(value)) return py::cast<std::string>(value);
  return py::cast<std::string>(py::module_::import("json").attr("dumps")(value));
}

// Calls f(scene) with the GIL released; the reply, or the package's exception.
template <class F>
SceneReply ask(SceneHandle& h, F&& f) {
  SceneClient& scene = h.get();
  SceneReply r;
  {
    py::gil_scoped_release release;
    r = f(scene);
  }
  if (!r.answered) raise_timeout(r.message);
  if (!r.accepted) raise_refused(r.message);
  return r;
}

}  // namespace

void bind_scene(py::module_& m, py::class_<ClientHandle>& client) {
  py::class_<SceneHandle>(m, "Scene", R"(The session's haptic scene (docs/haptic-scene.md), from Client.scene(): claim
it, add objects (a dict or JSON, as the scene file writes one), upload meshes, move moving objects at the engine's
frame rate, change materials, remove objects, and ask for the objects and for what every device's hand does to them.
A refused edit raises RequestRefused with the server's reason, no answer in time Timeout.)")
      .def(
          "claim",
          [](SceneHandle& h, double timeout_s) {
            return ask(h, [&](SceneClient& s) { return s.claim(Timeout(timeout_s)); }).message;
          },
          py::arg("timeout") = 2.0, "Become the scene's owner (only the owner edits).")
      .def(
          "release",
          [](SceneHandle& h, double timeout_s) {
            return ask(h, [&](SceneClient& s) { return s.release(Timeout(timeout_s)); }).message;
          },
          py::arg("timeout") = 2.0)
      .def(
          "add",
          [](SceneHandle& h, const py::object& object, double timeout_s) {
            const std::string text = json_of(object);
            return ask(h, [&](SceneClient& s) { return s.add(text, Timeout(timeout_s)); }).message;
          },
          py::arg("object"), py::arg("timeout") = 2.0,
          "object: a dict (or its JSON) as the scene file writes one: name, shape, sizes, position/pose, material, "
          "moving.")
      .def(
          "add_mesh",
          [](SceneHandle& h, const py::object& object,
             const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
             const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& triangles, double timeout_s) {
            const std::string text = json_of(object);
            if (vertices.size() % 3 != 0 || triangles.size() % 3 != 0)
              throw py::value_error("vertices and triangles come three numbers each (N x 3)");
            std::vector<std::uint32_t> t(static_cast<std::size_t>(triangles.size()));
            for (py::ssize_t i = 0; i < triangles.size(); ++i) {
              const std::int64_t k = triangles.data()[i];
              if (k < 0 || k > std::numeric_limits<std::uint32_t>::max())
                throw py::value_error("triangles: a vertex index out of 0..2^32-1");
              t[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(k);
            }
            const std::span<const double> v(vertices.data(), static_cast<std::size_t>(vertices.size()));
            return ask(h, [&](SceneClient& s) { return s.add_mesh(text, v, t, Timeout(timeout_s)); }).message;
          },
          py::arg("object"), py::arg("vertices"), py::arg("triangles"), py::arg("timeout") = 10.0,
          "A mesh: object as for add (shape 'mesh', no file); vertices N x 3 (m, the object's frame), triangles M x 3 "
          "vertex indices. Uploaded in parts, then checked and built by the server.")
      .def(
          "remove",
          [](SceneHandle& h, const std::string& name, double timeout_s) {
            return ask(h, [&](SceneClient& s) { return s.remove(name, Timeout(timeout_s)); }).message;
          },
          py::arg("name"), py::arg("timeout") = 2.0)
      .def(
          "set_material",
          [](SceneHandle& h, const std::string& name, const py::object& material, double timeout_s) {
            const std::string text = json_of(material);
            return ask(h, [&](SceneClient& s) { return s.set_material(name, text, Timeout(timeout_s)); }).message;
          },
          py::arg("name"), py::arg("material"), py::arg("timeout") = 2.0,
          "material: a name from the scene's materials, or a dict (stiffness, damping, friction...).")
      .def(
          "move", [](SceneHandle& h, const std::string& name, const Pose& pose) { return h.get().move(name, pose); },
          py::arg("name"), py::arg("pose"),
          "A moving object's new pose (not waited for; refused_moves counts refusals). False: not written.")
      .def(
          "objects",
          [](SceneHandle& h, double timeout_s) {
            return ask(h, [&](SceneClient& s) { return s.objects(Timeout(timeout_s)); }).objects;
          },
          py::arg("timeout") = 2.0, "Every object (SceneObject: name, shape, uid, moving, triangles, pose).")
      .def(
          "contacts",
          [](SceneHandle& h, double timeout_s) {
            return ask(h, [&](SceneClient& s) { return s.contacts(Timeout(timeout_s)); }).contacts;
          },
          py::arg("timeout") = 2.0,
          "What every device's hand does to the objects now (SceneContact: device, object_name, force and torque "
          "on the object - N, N m about its origin -, point).")
      .def_property_readonly("refused_moves", [](SceneHandle& h) { return h.get().refused_moves(); })
      .def_property_readonly("last_refusal", [](SceneHandle& h) { return h.get().last_refusal(); });
  client.def(
      "scene", [](ClientHandle& h) { return SceneHandle{&h}; }, py::keep_alive<0, 1>(),
      "The session's haptic scene (made on first use, on this client's participant).");
}

}  // namespace hapticd::python
