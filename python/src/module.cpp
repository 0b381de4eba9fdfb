// _hapticd: the extension module of the Python package hapticd (docs/python.md).
#include <exception>
#include <stdexcept>

#include "bindings.hpp"

namespace hapticd::python {

namespace {
// The exception classes live in hapticd.errors (plain Python, with docstrings); looked up when raised.
[[noreturn]] void raise(const char* name, const std::string& message) {
  const py::object type = py::module_::import("hapticd.errors").attr(name);
  PyErr_SetObject(type.ptr(), py::str(message).ptr());
  throw py::error_already_set();
}
}  // namespace

void raise_refused(const std::string& message) { raise("RequestRefused", message); }
void raise_timeout(const std::string& message) { raise("Timeout", message); }
void raise_session_error(const std::string& message) { raise("SessionError", message); }

}  // namespace hapticd::python

PYBIND11_MODULE(_hapticd, m) {
  m.doc() = "hapticd's client library and in-process session API (the hapticd package re-exports them)";
  // Anything else the library throws (a client that cannot join its domain, a closed client): hapticd.Error.
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const pybind11::builtin_exception&) {
      throw;  // ValueError, KeyError, ...: pybind11's own translation
    } catch (const std::runtime_error& e) {
      const pybind11::object type = pybind11::module_::import("hapticd.errors").attr("Error");
      PyErr_SetString(type.ptr(), e.what());
    }
  });
  hapticd::python::bind_spatial(m);
  hapticd::python::bind_client(m);
  hapticd::python::bind_engine(m);
  hapticd::python::bind_session(m);
}
