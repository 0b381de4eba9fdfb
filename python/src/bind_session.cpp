// The in-process session API (hapticd/server/session.hpp) as hapticd.Session: build from a session file or YAML
// text, step in lockstep (the GIL released), read every device's view, its ground truth and whole runs as NumPy
// arrays, feed engine input, make requests.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <map>
#include <stdexcept>

#include "bindings.hpp"
#include "convert.hpp"
#include "hapticd/server/session.hpp"

namespace hapticd::python {

namespace {

using server::DeviceRequest;
using server::DeviceView;
using server::Session;

// Runs f, turning the session's errors into SessionError (configuration errors name file, line and key).
template <class F>
auto guarded(F&& f) {
  try {
    return f();
  } catch (const py::error_already_set&) {
    throw;
  } catch (const std::out_of_range& e) {
    throw py::key_error(e.what());
  } catch (const std::exception& e) {
    raise_session_error(e.what());
  }
}

std::string answer(const RuntimeReply& r) {
  if (!r.accepted) raise_refused(r.message);
  return r.message;
}

// A run recorded cycle by cycle: columns of NumPy arrays (rows: the recorded cycles).
struct Columns {
  std::map<std::string, std::vector<double>> data;
  std::map<std::string, py::ssize_t> width;
  void add(const std::string& name, const double* v, py::ssize_t n) {
    auto& column = data[name];
    width[name] = n;
    column.insert(column.end(), v, v + n);
  }
  void add(const std::string& name, double v) { add(name, &v, 1); }
  void add(const std::string& name, const Eigen::Vector3d& v) { add(name, v.data(), 3); }
  void add(const std::string& name, const JointVector& v) { add(name, v.data(), v.size()); }
  py::dict to_dict() const {
    py::dict d;
    for (const auto& [name, column] : data) {
      const py::ssize_t w = width.at(name);
      const py::ssize_t rows = w == 0 ? 0 : static_cast<py::ssize_t>(column.size()) / w;
      py::array_t<double> a = w == 1 ? py::array_t<double>(rows) : py::array_t<double>({rows, w});
      std::copy(column.begin(), column.end(), a.mutable_data());
      d[py::str(name)] = a;
    }
    return d;
  }
};

void record_row(Columns& c, const DeviceView& v) {
  c.add("time_s", v.time_s);
  c.add("position", v.handle_pose.position);
  const Eigen::Quaterniond& q = v.handle_pose.orientation;
  const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
  c.add("orientation", wxyz, 4);
  c.add("velocity", v.handle_twist.linear);
  c.add("angular_velocity", v.handle_twist.angular);
  c.add("operator_force", v.operator_wrench.force);
  c.add("operator_torque", v.operator_wrench.torque);
  c.add("target_position", v.task.pose.position);
  c.add("target_force", v.task.wrench.force);
  c.add("joint_position", v.state.joints.position);
  c.add("joint_velocity", v.state.joints.velocity);
  c.add("joint_torque", v.command.torque_nm);
  c.add("engine_weight", v.engine_weight);
  c.add("faulted", v.fault.empty() ? 0.0 : 1.0);
  if (v.truth) {
    c.add("true_position", v.truth->handle_pose.position);
    c.add("true_velocity", v.truth->handle_twist.linear);
    c.add("true_operator_force", v.truth->handle_wrench.force);
  }
}

void bind_views(py::module_& m) {
  py::class_<SimulatedTruth>(m, "SimulatedTruth", "A simulated device's true state (what no sensor reports).")
      .def_readonly("time_s", &SimulatedTruth::time_s)
      .def_property_readonly("link_position", [](const SimulatedTruth& t) { return joint_array(t.link_position); })
      .def_property_readonly("link_velocity", [](const SimulatedTruth& t) { return joint_array(t.link_velocity); })
      .def_property_readonly("motor_position", [](const SimulatedTruth& t) { return joint_array(t.motor_position); })
      .def_property_readonly("motor_velocity", [](const SimulatedTruth& t) { return joint_array(t.motor_velocity); })
      .def_property_readonly("friction_torque", [](const SimulatedTruth& t) { return joint_array(t.friction_torque); })
      .def_property_readonly("motor_torque", [](const SimulatedTruth& t) { return joint_array(t.motor_torque); })
      .def_readonly("handle_pose", &SimulatedTruth::handle_pose)
      .def_readonly("handle_twist", &SimulatedTruth::handle_twist)
      .def_readonly("handle_wrench", &SimulatedTruth::handle_wrench, "what holds the handle applies to it");

  py::class_<DeviceView>(m, "DeviceView", "One device after the last step.")
      .def_readonly("name", &DeviceView::name)
      .def_readonly("cycle", &DeviceView::cycle)
      .def_readonly("time_s", &DeviceView::time_s)
      .def_property_readonly("joint_position", [](const DeviceView& v) { return joint_array(v.state.joints.position); })
      .def_property_readonly(
          "joint_velocity", [](const DeviceView& v) { return joint_array(v.state.joints.velocity); },
          "the server's one estimate")
      .def_property_readonly(
          "joint_effort", [](const DeviceView& v) { return joint_array(v.state.joints.effort); },
          "measured joint torques, where the device has sensors")
      .def_property_readonly(
          "joint_torque", [](const DeviceView& v) { return joint_array(v.command.torque_nm); },
          "the torque written (after the safety supervisor)")
      .def_readonly("handle_pose", &DeviceView::handle_pose)
      .def_readonly("handle_twist", &DeviceView::handle_twist)
      .def_readonly("operator_wrench", &DeviceView::operator_wrench)
      .def_property_readonly(
          "buttons", [](const DeviceView& v) { return v.state.handle.buttons; },
          "the handle's buttons, bit i: button i pressed")
      .def_property_readonly(
          "gripper", [](const DeviceView& v) { return v.state.handle.gripper; }, "the gripper's opening (rad)")
      .def_property_readonly("target_pose", [](const DeviceView& v) { return v.task.pose; })
      .def_property_readonly("target_twist", [](const DeviceView& v) { return v.task.twist; })
      .def_property_readonly("target_wrench", [](const DeviceView& v) { return v.task.wrench; })
      .def_readonly("scheme", &DeviceView::scheme)
      .def_readonly("fault", &DeviceView::fault, "'' while running, else the fault holding it in its safe mode")
      .def_readonly("at_rest", &DeviceView::at_rest)
      .def_readonly("engine_weight", &DeviceView::engine_weight)
      .def_readonly("faults", &DeviceView::faults)
      .def_readonly("recoveries", &DeviceView::recoveries)
      .def_readonly("scheme_switches", &DeviceView::scheme_switches)
      .def_readonly("refused_switches", &DeviceView::refused_switches)
      .def_readonly("saturated_cycles", &DeviceView::saturated_cycles)
      .def_readonly("limited_cycles", &DeviceView::limited_cycles)
      .def_readonly("render_limited_cycles", &DeviceView::render_limited_cycles)
      .def_readonly("thermal_load", &DeviceView::thermal_load)
      .def_readonly("dissipated_j", &DeviceView::dissipated_j)
      .def_readonly("truth", &DeviceView::truth, "the simulated device's true state; None for hardware")
      .def("__repr__", [](const DeviceView& v) {
        return "DeviceView('" + v.name + "', cycle=" + std::to_string(v.cycle) + ", scheme='" + v.scheme +
               "', fault='" + v.fault + "')";
      });

  py::class_<JointDescription>(m, "JointDescription")
      .def_readonly("name", &JointDescription::name)
      .def_readonly("position_min", &JointDescription::position_min)
      .def_readonly("position_max", &JointDescription::position_max)
      .def_readonly("velocity_max", &JointDescription::velocity_max)
      .def_readonly("torque_peak_nm", &JointDescription::torque_peak_nm)
      .def_readonly("torque_continuous_nm", &JointDescription::torque_continuous_nm);

  py::class_<DeviceDescription>(m, "DeviceDescription", "What a device plugin says about itself.")
      .def_readonly("model", &DeviceDescription::model)
      .def_readonly("joints", &DeviceDescription::joints)
      .def_property_readonly("dof", &DeviceDescription::dof)
      .def_readonly("handle_frame", &DeviceDescription::handle_frame)
      .def_readonly("robot_model_file", &DeviceDescription::robot_model_file)
      .def_readonly("simulated", &DeviceDescription::simulated)
      .def_readonly("base_pose", &DeviceDescription::base_pose);

  py::class_<server::SessionStatistics>(m, "SessionStatistics", "Cycles run and this machine's compute time.")
      .def_readonly("cycles", &server::SessionStatistics::cycles)
      .def_readonly("time_s", &server::SessionStatistics::time_s)
      .def_readonly("compute_p50_us", &server::SessionStatistics::compute_p50_us)
      .def_readonly("compute_p99_us", &server::SessionStatistics::compute_p99_us)
      .def_readonly("compute_max_us", &server::SessionStatistics::compute_max_us);

  py::class_<EngineInput>(m, "EngineInput", "A rendering engine's input for a device (as one that came over DDS).")
      .def_static(
          "coupling",
          [](const Pose& proxy, const Twist& twist) {
            EngineInput in;
            in.proxy_pose = proxy;
            in.proxy_twist = twist;
            in.has_proxy = true;
            return in;
          },
          py::arg("proxy"), py::arg("proxy_twist") = Twist{}, "impedance type: the proxy for the virtual coupling")
      .def_static(
          "force",
          [](const Wrench& w) {
            EngineInput in;
            in.wrench = w;
            in.has_wrench = true;
            return in;
          },
          py::arg("wrench"), "impedance type: a wrench to display")
      .def_static(
          "motion",
          [](const Pose& pose, const Twist& twist) {
            EngineInput in;
            in.motion_pose = pose;
            in.motion_twist = twist;
            in.has_motion = true;
            return in;
          },
          py::arg("pose"), py::arg("twist") = Twist{}, "admittance type: the handle's desired motion")
      .def_readwrite("sequence", &EngineInput::sequence, "the engine's serial number (increasing)");
}

// One device request, answered or raised.
std::string device_request(Session& s, const std::string& device, DeviceRequest::Kind kind, std::string name = {},
                           std::vector<double> values = {}) {
  const RuntimeReply r = guarded([&] {
    return s.request(device, DeviceRequest{kind, std::move(name), std::move(values)});
  });
  return answer(r);
}

}  // namespace

void bind_session(py::module_& m) {
  bind_views(m);
  using Kind = DeviceRequest::Kind;
  py::class_<Session>(m, "Session", R"(A hapticd session in this process, stepped in lockstep on a virtual clock: the
server's own cycle, repeatable and independent of the machine's speed. Not thread-safe: one thread drives it.)")
      .def_static(
          "from_file",
          [](const std::filesystem::path& file, const std::vector<std::string>& overrides,
             const std::vector<std::filesystem::path>& plugin_paths) {
            return guarded([&] { return Session::from_file(file, {overrides, plugin_paths}); });
          },
          py::arg("file"), py::arg("overrides") = std::vector<std::string>{},
          py::arg("plugin_paths") = std::vector<std::filesystem::path>{},
          "overrides: 'path=value' (YAML value), e.g. 'server.seed=7'; raises SessionError naming file, line and key")
      .def_static(
          "from_yaml",
          [](const std::string& yaml, const std::vector<std::string>& overrides,
             const std::vector<std::filesystem::path>& plugin_paths, const std::string& name) {
            return guarded([&] { return Session::from_yaml(yaml, {overrides, plugin_paths}, name); });
          },
          py::arg("yaml"), py::arg("overrides") = std::vector<std::string>{},
          py::arg("plugin_paths") = std::vector<std::filesystem::path>{}, py::arg("name") = "<session>",
          "session-file text; relative paths from the working directory; name stands for the file in errors")
      .def(
          "__enter__", [](Session& s) -> Session& { return s; }, py::return_value_policy::reference)
      .def("__exit__", [](Session& s, const py::args&) { guarded([&] { s.stop(); }); })
      .def_property_readonly("device_names", &Session::device_names)
      .def_property_readonly("period_s", &Session::period_s)
      .def_property_readonly("cycles_run", &Session::cycles_run)
      .def(
          "step",
          [](Session& s, std::uint64_t cycles) {
            guarded([&] {
              py::gil_scoped_release release;
              s.step(cycles);
            });
          },
          py::arg("cycles") = 1, "run cycles (the first step powers the devices)")
      .def(
          "run",
          [](Session& s, std::uint64_t cycles, const std::string& device, std::uint64_t every) {
            if (every == 0) throw py::value_error("every: at least 1");
            Columns columns;
            guarded([&] {
              (void)s.device(device);  // KeyError before running anything
              py::gil_scoped_release release;
              for (std::uint64_t done = 0; done < cycles; done += every) {
                s.step(std::min(every, cycles - done));
                record_row(columns, s.device(device));
              }
            });
            return columns.to_dict();
          },
          py::arg("cycles"), py::arg("device"), py::arg("every") = 1,
          R"(Step `cycles` cycles and record the device every `every` cycles: a dict of NumPy arrays (one row per
record) - time_s, position, orientation [w x y z], velocity, angular_velocity, operator_force, operator_torque,
target_position, target_force, joint_position, joint_velocity, joint_torque, engine_weight, faulted, and on
simulated devices true_position, true_velocity, true_operator_force.)")
      .def(
          "device", [](const Session& s, const std::string& name) { return guarded([&] { return s.device(name); }); },
          py::arg("name"), "the device after the last step (KeyError for a device the session does not have)")
      .def(
          "description",
          [](const Session& s, const std::string& name) { return guarded([&] { return s.description(name); }); },
          py::arg("name"))
      .def(
          "set_engine_input",
          [](Session& s, const std::string& device, const EngineInput& input) {
            guarded([&] { s.set_engine_input(device, input); });
          },
          py::arg("device"), py::arg("input"), "picked up by the next cycle")
      .def(
          "switch_scheme",
          [](Session& s, const std::string& d, const std::string& scheme) {
            return device_request(s, d, Kind::switch_scheme, scheme);
          },
          py::arg("device"), py::arg("scheme"))
      .def(
          "set_parameter",
          [](Session& s, const std::string& d, const std::string& parameter, const py::object& values) {
            return device_request(s, d, Kind::set_parameter, parameter, values_of(values));
          },
          py::arg("device"), py::arg("parameter"), py::arg("values"))
      .def(
          "get_parameter",
          [](Session& s, const std::string& d, const std::string& parameter) {
            const RuntimeReply r = guarded([&] {
              return s.request(d, DeviceRequest{Kind::get_parameter, parameter, {}});
            });
            answer(r);
            return r.values;
          },
          py::arg("device"), py::arg("parameter"))
      .def(
          "parameters",
          [](Session& s, const std::string& d) {
            py::list out;
            for (std::size_t k = 0, count = 1; k < count; ++k) {
              const RuntimeReply r = guarded([&] {
                return s.request(d, DeviceRequest{Kind::describe_parameter, {}, {static_cast<double>(k)}});
              });
              answer(r);
              const std::optional<DescribedParameter> described = decode_parameter_info(r.message, r.values);
              if (!described) raise_session_error("unreadable parameter description: " + r.message);
              count = described->count;
              out.append(parameter_dict(described->info));
            }
            return out;
          },
          py::arg("device"),
          "every parameter of the device: dicts of name, type, unit, description, tunable, minimum, maximum, "
          "minimum_exclusive, value, value_text")
      .def(
          "operator",
          [](Session& s, const std::string& d, const std::string& command, const py::object& values) {
            return device_request(s, d, Kind::drive_operator, command, values_of(values));
          },
          py::arg("device"), py::arg("command"), py::arg("values") = py::none())
      .def(
          "estop", [](Session& s, const std::string& d) { return device_request(s, d, Kind::emergency_stop); },
          py::arg("device"))
      .def(
          "recover", [](Session& s, const std::string& d) { return device_request(s, d, Kind::recover); },
          py::arg("device"))
      .def("statistics", &Session::statistics)
      .def(
          "stop", [](Session& s) { guarded([&] { s.stop(); }); },
          "ramp the torques to zero and deactivate the devices; nothing can be stepped afterwards");
}

}  // namespace hapticd::python
