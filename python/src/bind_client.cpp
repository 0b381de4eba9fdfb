// The DDS client library (hapticd/client/client.hpp) as hapticd.Client with its value types. Every call that can
// block (waiting for a device, a state, a reply) releases the GIL. Python code never runs on the library's
// threads: states, events, telemetry and fault reports are polled or waited for (the C++ callbacks are not
// offered).
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <memory>
#include <stdexcept>

#include "bindings.hpp"
#include "client_handle.hpp"
#include "convert.hpp"
#include "hapticd/client/client.hpp"

namespace hapticd::python {

namespace {

using namespace hapticd::client;

Timeout seconds(double s) { return Timeout(s); }

// The reply's message when accepted; else the package's exception with the server's message.
std::string answer(const Reply& r) {
  if (!r.answered) raise_timeout(r.message);
  if (!r.accepted) raise_refused(r.message);
  return r.message;
}

// Calls f(client) with the GIL released and turns its reply into a message or an exception.
template <class F>
std::string request(ClientHandle& h, F&& f) {
  Client& c = h.get();
  Reply r;
  {
    py::gil_scoped_release release;
    r = f(c);
  }
  return answer(r);
}

template <class T>
T or_timeout(std::optional<T>&& value, const std::string& what) {
  if (!value) raise_timeout(what);
  return std::move(*value);
}

#include "hapticd_wire/python_fields.inc"

// The value classes: generated from idl/hapticd_wire.toml (python_fields.inc), with what the table leaves to them.
void bind_types(py::module_& m) {
  bind_Mode(m);
  bind_EventKind(m);
  m.def("flag_names", &flag_names, py::arg("flags"), "The names of the set DeviceState flags, lowest bit first.");
  bind_LoopSummary(m);
  bind_SchemeInfo(m);
  bind_DeviceInfo(m).def("__repr__", [](const DeviceInfo& d) {
    return "DeviceInfo('" + d.device + "', " + d.device_plugin + ", " + std::to_string(d.dof) + " joints)";
  });
  bind_DeviceState(m)
      .def_property_readonly("time_s", &DeviceState::time_s, "loop_time_ns in seconds")
      .def_property_readonly(
          "flag_names", [](const DeviceState& s) { return flag_names(s.flags); }, "the names of the set flags")
      .def("__repr__", [](const DeviceState& s) {
        return "DeviceState('" + s.device.str() + "', serial=" + std::to_string(s.serial) +
               ", t=" + std::to_string(s.time_s()) + " s, " + std::string(to_string(s.mode)) + ")";
      });
  bind_GroupInfo(m);
  bind_GroupState(m).def_property_readonly("states", [](const GroupState& g) {
    return std::vector<DeviceState>(g.states.begin(), g.states.begin() + g.device_count);
  });
  bind_Event(m).def("__repr__", [](const Event& e) {
    return "Event('" + e.device + "', " + std::string(to_string(e.kind)) + ", '" + e.code + "')";
  });
  bind_Telemetry(m);
  bind_CycleRecord(m);
  bind_FaultReport(m);
  bind_SceneObject(m).def("__repr__", [](const SceneObject& o) {
    return "SceneObject('" + o.name + "', " + o.shape + (o.moving ? ", moving)" : ")");
  });
  bind_SceneContact(m).def(
      "__repr__", [](const SceneContact& c) { return "SceneContact('" + c.device + "' on '" + c.object_name + "')"; });

  using Vector6 = Eigen::Matrix<double, 6, 1>;
  py::class_<LocalModel>(m, "LocalModel", R"(A wrench command's local model: every cycle until the next command the
server applies wrench + stiffness * (anchor - x) - damping * velocity (6 values each: N/m, N m/rad; N s/m, N m s/rad).)")
      .def(py::init([](const Pose& anchor, const Vector6& stiffness, const Vector6& damping) {
             return LocalModel{anchor, stiffness, damping};
           }),
           py::arg("anchor"), py::arg("stiffness"), py::arg("damping") = Vector6::Zero().eval())
      .def_static(
          "spring",
          [](const Pose& anchor, const Eigen::Vector3d& stiffness, const Eigen::Vector3d& damping) {
            LocalModel model{anchor, Vector6::Zero(), Vector6::Zero()};
            model.stiffness.head<3>() = stiffness;
            model.damping.head<3>() = damping;
            return model;
          },
          py::arg("anchor"), py::arg("stiffness"), py::arg("damping") = Eigen::Vector3d::Zero().eval(),
          "a translational spring-damper about the anchor's position (N/m and N s/m per axis)")
      .def_readwrite("anchor", &LocalModel::anchor)
      .def_readwrite("stiffness", &LocalModel::stiffness)
      .def_readwrite("damping", &LocalModel::damping);

  py::class_<EngineCommand>(m, "EngineCommand", "What an engine sends a device; made by coupling, force or motion.")
      .def_static("coupling", &EngineCommand::coupling, py::arg("proxy"), py::arg("proxy_twist") = Twist{},
                  py::arg("state_serial") = 0, "impedance type: the proxy the virtual coupling ties the handle to")
      .def_static(
          "force",
          [](const Wrench& wrench, std::uint64_t state_serial, std::optional<LocalModel> local_model) {
            EngineCommand c = EngineCommand::force(wrench, state_serial);
            c.local_model = std::move(local_model);
            return c;
          },
          py::arg("wrench"), py::arg("state_serial") = 0, py::arg("local_model") = py::none(),
          "impedance type: a wrench to display, with an optional local model the server applies every cycle")
      .def_static("motion", &EngineCommand::motion, py::arg("pose"), py::arg("twist") = Twist{},
                  py::arg("state_serial") = 0, "admittance type: the handle's desired motion")
      .def_readwrite("state_serial", &EngineCommand::state_serial);
}

}  // namespace

void bind_client(py::module_& m) {
  bind_types(m);
  py::class_<ClientHandle> client_class(m, "Client",
                                        R"(A client of hapticd's DDS interface: one DDS participant (loopback only by
default). Waiting calls release the GIL; a refused request raises RequestRefused, no reply in time Timeout.)");
  client_class
      .def(py::init([](const std::string& client_id, int domain, const std::string& cyclone_config,
                       const std::string& network, double command_deadline_s) {
             ClientOptions options(client_id, domain);
             options.cyclone_config = cyclone_config;
             options.network = network;
             options.command_deadline_s = command_deadline_s;
             return ClientHandle{std::make_unique<Client>(std::move(options))};
           }),
           py::arg("client_id"), py::arg("domain") = 0, py::arg("cyclone_config") = "", py::arg("network") = "",
           py::arg("command_deadline_s") = 0.05,
           "network: 'interfaces=eth1;peers=192.0.2.2;multicast=false' (default: HAPTICD_DDS_NETWORK, else loopback)")
      .def_property_readonly("id", [](ClientHandle& h) { return h.get().id(); })
      .def(
          "close",
          [](ClientHandle& h) {
            py::gil_scoped_release release;
            h.client.reset();
          },
          "leave the domain (claims end with the participant)")
      .def("__enter__", [](ClientHandle& h) -> ClientHandle& { return h; })
      .def("__exit__",
           [](ClientHandle& h, const py::args&) {
             py::gil_scoped_release release;
             h.client.reset();
           })
      // ---- devices and states ----
      .def(
          "devices", [](ClientHandle& h) { return h.get().devices(); }, "the descriptions received so far")
      .def(
          "wait_for_device",
          [](ClientHandle& h, const std::string& device, double timeout, bool started) {
            std::optional<DeviceInfo> d;
            {
              py::gil_scoped_release release;
              d = h.get().wait_for_device(device, seconds(timeout), started);
            }
            return or_timeout(std::move(d), "no device '" + device + "' within the timeout");
          },
          py::arg("device"), py::arg("timeout") = 5.0, py::arg("started") = false,
          "the device's description (with started: once it carries the start pose)")
      .def(
          "latest_state", [](ClientHandle& h, const std::string& device) { return h.get().latest_state(device); },
          py::arg("device"), "the newest state, or None")
      .def(
          "wait_for_state",
          [](ClientHandle& h, const std::string& device, double timeout, std::uint64_t after) {
            std::optional<DeviceState> s;
            {
              py::gil_scoped_release release;
              s = h.get().wait_for_state(device, seconds(timeout), after);
            }
            return or_timeout(std::move(s), "no state of '" + device + "' within the timeout");
          },
          py::arg("device"), py::arg("timeout") = 1.0, py::arg("after") = 0,
          "the newest state with serial > after (waits for it)")
      .def("groups", [](ClientHandle& h) { return h.get().groups(); })
      .def(
          "wait_for_group",
          [](ClientHandle& h, const std::string& group, double timeout) {
            std::optional<GroupInfo> g;
            {
              py::gil_scoped_release release;
              g = h.get().wait_for_group(group, seconds(timeout));
            }
            return or_timeout(std::move(g), "no group '" + group + "' within the timeout");
          },
          py::arg("group"), py::arg("timeout") = 5.0)
      .def(
          "wait_for_group_state",
          [](ClientHandle& h, const std::string& group, double timeout, std::uint64_t after) {
            std::optional<GroupState> g;
            {
              py::gil_scoped_release release;
              g = h.get().wait_for_group_state(group, seconds(timeout), after);
            }
            return or_timeout(std::move(g), "no state of group '" + group + "' within the timeout");
          },
          py::arg("group"), py::arg("timeout") = 1.0, py::arg("after") = 0)
      .def(
          "latest_group_state",
          [](ClientHandle& h, const std::string& group) { return h.get().latest_group_state(group); }, py::arg("group"),
          "the newest group state, or None")
      // ---- events, telemetry, fault reports ----
      .def(
          "take_events", [](ClientHandle& h) { return h.get().take_events(); },
          "the events received since the last call, oldest first")
      .def(
          "latest_telemetry",
          [](ClientHandle& h, const std::string& device) { return h.get().latest_telemetry(device); },
          py::arg("device"))
      .def(
          "latest_fault_report",
          [](ClientHandle& h, const std::string& device) { return h.get().latest_fault_report(device); },
          py::arg("device"), "the newest fault report of the device, or None")
      // ---- requests ----
      .def(
          "claim",
          [](ClientHandle& h, const std::string& d, double t) {
            return request(h, [&](Client& c) { return c.claim(d, seconds(t)); });
          },
          py::arg("device"), py::arg("timeout") = 2.0, "become the device's engine")
      .def(
          "claim_lost", [](ClientHandle& h, const std::string& d) { return h.get().claim_lost(d); }, py::arg("device"),
          "whether this client's newest claim of the device ended without its release (the server's claim hold "
          "ran out: claim again or stop)")
      .def(
          "release",
          [](ClientHandle& h, const std::string& d, double t) {
            return request(h, [&](Client& c) { return c.release(d, seconds(t)); });
          },
          py::arg("device"), py::arg("timeout") = 2.0)
      .def(
          "switch_scheme",
          [](ClientHandle& h, const std::string& d, const std::string& scheme, double t) {
            return request(h, [&](Client& c) { return c.switch_scheme(d, scheme, seconds(t)); });
          },
          py::arg("device"), py::arg("scheme"), py::arg("timeout") = 2.0)
      .def(
          "set_parameter",
          [](ClientHandle& h, const std::string& d, const std::string& parameter, const py::object& values, double t) {
            const std::vector<double> v = values_of(values);
            return request(h, [&](Client& c) { return c.set_parameter(d, parameter, v, seconds(t)); });
          },
          py::arg("device"), py::arg("parameter"), py::arg("values"), py::arg("timeout") = 2.0,
          "parameter: '<stage>.<name>', e.g. 'virtual_model.mass_kg'; values: a number or a sequence")
      .def(
          "get_parameter",
          [](ClientHandle& h, const std::string& d, const std::string& parameter, double t) {
            Client& c = h.get();
            Reply r;
            {
              py::gil_scoped_release release;
              r = c.get_parameter(d, parameter, seconds(t));
            }
            answer(r);
            return r.values;
          },
          py::arg("device"), py::arg("parameter"), py::arg("timeout") = 2.0,
          "the value in effect, as a list (a boolean as 0 or 1)")
      .def(
          "parameters",
          [](ClientHandle& h, const std::string& d, double t) {
            Client& c = h.get();
            Client::ParameterList list;
            {
              py::gil_scoped_release release;
              list = c.parameters(d, seconds(t));
            }
            answer(list.reply);
            py::list out;
            for (const ParameterInfo& p : list.parameters) out.append(parameter_dict(p));
            return out;
          },
          py::arg("device"), py::arg("timeout") = 2.0,
          "every parameter of the device: dicts of name, type, unit, description, tunable, minimum, maximum, "
          "minimum_exclusive, value, value_text")
      .def(
          "estop",
          [](ClientHandle& h, const std::string& d, double t) {
            return request(h, [&](Client& c) { return c.emergency_stop(d, seconds(t)); });
          },
          py::arg("device"), py::arg("timeout") = 2.0, "emergency stop: the device goes to its safe mode")
      .def(
          "recover",
          [](ClientHandle& h, const std::string& d, double t) {
            return request(h, [&](Client& c) { return c.recover(d, seconds(t)); });
          },
          py::arg("device"), py::arg("timeout") = 2.0, "leave the safe mode")
      .def(
          "operator",
          [](ClientHandle& h, const std::string& d, const std::string& command, const py::object& values, double t) {
            const std::vector<double> v = values_of(values);
            return request(h, [&](Client& c) { return c.operator_command(d, command, v, seconds(t)); });
          },
          py::arg("device"), py::arg("command"), py::arg("values") = py::none(), py::arg("timeout") = 2.0,
          "a simulated device's operator: push [fx, fy, fz, ramp_s], move [dx, dy, dz, duration_s], grasp [g], "
          "release")
      .def(
          "claim_group",
          [](ClientHandle& h, const std::string& g, double t) {
            return request(h, [&](Client& c) { return c.claim_group(g, seconds(t)); });
          },
          py::arg("group"), py::arg("timeout") = 2.0, "claim every device of the group, or none")
      .def(
          "release_group",
          [](ClientHandle& h, const std::string& g, double t) {
            return request(h, [&](Client& c) { return c.release_group(g, seconds(t)); });
          },
          py::arg("group"), py::arg("timeout") = 2.0)
      .def(
          "estop_group",
          [](ClientHandle& h, const std::string& g, double t) {
            return request(h, [&](Client& c) { return c.emergency_stop_group(g, seconds(t)); });
          },
          py::arg("group"), py::arg("timeout") = 2.0, "group '*': every device of every server on the domain")
      .def(
          "recover_group",
          [](ClientHandle& h, const std::string& g, double t) {
            return request(h, [&](Client& c) { return c.recover_group(g, seconds(t)); });
          },
          py::arg("group"), py::arg("timeout") = 2.0)
      // ---- engine commands ----
      .def(
          "send", [](ClientHandle& h, const std::string& d, const EngineCommand& c) { return h.get().send(d, c); },
          py::arg("device"), py::arg("command"), "False when it could not be written")
      .def(
          "send_coupling",
          [](ClientHandle& h, const std::string& d, const Pose& proxy, const Twist& twist, std::uint64_t serial) {
            return h.get().send_coupling(d, proxy, twist, serial);
          },
          py::arg("device"), py::arg("proxy"), py::arg("proxy_twist") = Twist{}, py::arg("state_serial") = 0)
      .def(
          "send_wrench",
          [](ClientHandle& h, const std::string& d, const Wrench& w, std::uint64_t serial) {
            return h.get().send_wrench(d, w, serial);
          },
          py::arg("device"), py::arg("wrench"), py::arg("state_serial") = 0)
      .def(
          "send_motion",
          [](ClientHandle& h, const std::string& d, const Pose& pose, const Twist& twist, std::uint64_t serial) {
            return h.get().send_motion(d, pose, twist, serial);
          },
          py::arg("device"), py::arg("pose"), py::arg("twist") = Twist{}, py::arg("state_serial") = 0)
      .def(
          "send_group",
          [](ClientHandle& h, const std::string& group,
             const std::vector<std::pair<std::string, EngineCommand>>& commands) {
            std::vector<DeviceCommand> list;
            for (const auto& [device, command] : commands) list.push_back({Name(device), command});
            return h.get().send_group(group, list);
          },
          py::arg("group"), py::arg("commands"),
          "one command per device of a claimed group, in the group's order: [(device, EngineCommand), ...]");
  bind_scene(m, client_class);
}

}  // namespace hapticd::python
