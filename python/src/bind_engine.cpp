// hapticd.run_engine's C++ side (python/hapticd/engine.py): the client library's one engine helper
// (hapticd::client::Engine) with a Python function as its answer. The function runs on the client's receive
// thread, holding the GIL for the call only (run() releases it meanwhile); an exception it raises ends the run and is
// raised again in the caller.
#include <pybind11/stl.h>

#include <exception>

#include "bindings.hpp"
#include "client_handle.hpp"
#include "hapticd/client/engine.hpp"

namespace hapticd::python {

namespace {

using namespace hapticd::client;

// What one run did, for EngineStats (engine.py).
struct RunCounts {
  std::uint64_t last_serial = 0, skipped = 0, unanswered = 0, commands = 0;
  bool stopped_by_function = false;
  std::exception_ptr error;  // the function's exception, raised again after the run
};

py::dict run_engine(ClientHandle& handle, const std::string& device, const py::function& answer, double duration_s,
                    double timeout_s, double wait_s) {
  EngineOptions options;
  options.name = "run_engine";
  options.device = device;
  options.duration = Timeout(duration_s);
  options.server_timeout = Timeout(timeout_s);
  options.wait = Timeout(wait_s);
  Engine engine(handle.get(), options);
  RunCounts counts;
  EngineEnd end;
  {
    py::gil_scoped_release release;
    end = engine.run([&](std::span<const DeviceState* const> states, std::span<EngineCommand> commands) {
      if (counts.error || counts.stopped_by_function) return false;  // ending: the function is not called again
      const DeviceState& s = *states.front();
      if (counts.last_serial != 0 && s.serial > counts.last_serial + 1)
        counts.skipped += s.serial - counts.last_serial - 1;
      counts.last_serial = s.serial;
      py::gil_scoped_acquire gil;
      // The receive thread keeps its Python thread state from its first answer on: made and deleted for every
      // state it cost a round trip five times the C++ engine's (bench/python_engine_round_trip.py).
      static thread_local bool kept = false;
      if (!kept) gil.inc_ref();
      kept = true;
      try {
        const py::object reply = answer(s);
        if (reply.is_none()) {
          ++counts.unanswered;
          return false;
        }
        if (py::isinstance<py::bool_>(reply) && !reply.cast<bool>()) {
          counts.stopped_by_function = true;
          engine.stop();
          return false;
        }
        if (!py::isinstance<EngineCommand>(reply))
          throw py::type_error("the engine function returned " +
                               std::string(py::str(reply.get_type().attr("__name__"))) + ", not an EngineCommand");
        commands.front() = reply.cast<EngineCommand>();
        ++counts.commands;
        return true;
      } catch (...) {
        counts.error = std::current_exception();
        engine.stop();
        return false;
      }
    });
  }
  if (counts.error) std::rethrow_exception(counts.error);
  py::dict out;
  out["reason"] = static_cast<int>(end.reason);
  out["message"] = end.message;
  out["answered"] = engine.answered();
  out["skipped"] = counts.skipped;
  out["unanswered"] = counts.unanswered;
  out["send_failures"] = counts.commands - engine.answered();
  out["stopped_by_function"] = counts.stopped_by_function;
  return out;
}

}  // namespace

void bind_engine(py::module_& m) {
  m.def("_run_engine", &run_engine, py::arg("client"), py::arg("device"), py::arg("answer"), py::arg("duration_s"),
        py::arg("timeout_s"), py::arg("wait_s"), "hapticd.run_engine's engine helper (use run_engine)");
}

}  // namespace hapticd::python
