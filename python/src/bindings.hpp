#pragma once
// The parts of the extension module _hapticd (python/hapticd: the package around it), one file each.
#include <pybind11/pybind11.h>

#include <string>

namespace hapticd::python {

namespace py = pybind11;
struct ClientHandle;

void bind_spatial(py::module_& m);  // Pose, Twist, Wrench with NumPy fields
void bind_client(py::module_& m);   // the DDS client library: Client and its value types
void bind_scene(py::module_& m, py::class_<ClientHandle>& client);  // Scene, from Client.scene()
void bind_engine(py::module_& m);                                   // the engine helper under run_engine
void bind_session(py::module_& m);  // the in-process session API: Session, DeviceView, EngineInput

// Raise the package's exceptions (hapticd.errors): a refused request, no answer in time, a session that cannot
// be built or run. Each carries the server's message.
[[noreturn]] void raise_refused(const std::string& message);
[[noreturn]] void raise_timeout(const std::string& message);
[[noreturn]] void raise_session_error(const std::string& message);

}  // namespace hapticd::python
