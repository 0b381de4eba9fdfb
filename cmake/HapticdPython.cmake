# The Python interpreter hapticd's Python package and Python tools are built for (docs/python.md, "Which
# Python"): Python3_EXECUTABLE when given (-DPython3_EXECUTABLE=$(command -v python3) builds for the active
# interpreter: it needs NumPy, and pytest and h5py for the tests), else Debian's /usr/bin/python3, which
# scripts/install-deps.sh gives NumPy, Matplotlib, h5py and pytest. An interpreter of a version manager (pyenv,
# conda) first on PATH is not taken on its own: it rarely has those packages, and nothing is downloaded here.
#
# The tools carry that interpreter in their first line and the package's folder on their path, so they run the
# same whatever `python3` the user's shell finds; `hapticd-python` is that interpreter with the package on its
# path (`hapticd-python my_engine.py`).
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
find_package(Python3 3.9 REQUIRED COMPONENTS Interpreter)
set(HAPTICD_PYTHON "${Python3_EXECUTABLE}")

if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(_python_dir "lib/python3/dist-packages")  # Debian's place for packages of the system
else()
  set(_python_dir "lib/python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}/dist-packages")
endif()
set(HAPTICD_PYTHON_INSTALL_DIR "${_python_dir}" CACHE STRING "where the hapticd package installs, under the prefix")
set(HAPTICD_PYTHON_BUILD_DIR "${PROJECT_BINARY_DIR}/python")

# The package's folder relative to the programs' folder, in the build tree and once installed.
file(RELATIVE_PATH _build_rel "${CMAKE_RUNTIME_OUTPUT_DIRECTORY}" "${HAPTICD_PYTHON_BUILD_DIR}")
file(RELATIVE_PATH _install_rel "/prefix/${CMAKE_INSTALL_BINDIR}" "/prefix/${HAPTICD_PYTHON_INSTALL_DIR}")
set(HAPTICD_PYTHON_BUILD_REL "${_build_rel}" CACHE INTERNAL "")
set(HAPTICD_PYTHON_INSTALL_REL "${_install_rel}" CACHE INTERNAL "")

# Writes the program <name> twice - into the build tree's bin folder and, to be installed, into generated/install -
# with @HAPTICD_PACKAGE_REL@ in <content> replaced by the package's folder relative to the programs' folder there.
function(hapticd_write_program name content)
  foreach(where build install)
    if(where STREQUAL "build")
      set(_out "${CMAKE_RUNTIME_OUTPUT_DIRECTORY}/${name}")
      set(_rel "${HAPTICD_PYTHON_BUILD_REL}")
    else()
      set(_out "${PROJECT_BINARY_DIR}/generated/install/${name}")
      set(_rel "${HAPTICD_PYTHON_INSTALL_REL}")
    endif()
    string(REPLACE "@HAPTICD_PACKAGE_REL@" "${_rel}" _text "${content}")
    file(WRITE "${_out}" "${_text}")
    file(CHMOD "${_out}" PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ
      WORLD_EXECUTE)
  endforeach()
  install(PROGRAMS "${PROJECT_BINARY_DIR}/generated/install/${name}" DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()

# hapticd_add_python_program(<name> <script>): <script> as the program <name>: its first line names HAPTICD_PYTHON,
# the next puts the package's folder on sys.path.
function(hapticd_add_python_program name script)
  get_filename_component(script "${script}" ABSOLUTE)
  file(READ "${script}" text)
  string(REGEX REPLACE "^#![^\n]*\n" "" text "${text}")
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${script}")
  hapticd_write_program(${name} "#!${HAPTICD_PYTHON}
import os as _os, sys as _sys  # noqa: E401 (written by the build: the hapticd package's folder)
_sys.path.insert(0, _os.path.join(_os.path.dirname(_os.path.realpath(__file__)), \"@HAPTICD_PACKAGE_REL@\"))
${text}")
endfunction()

# hapticd-python: the interpreter above with the package's folder on PYTHONPATH, for the user's own scripts and the
# examples (`hapticd-python examples/python/wall_engine.py`); `hapticd-python --which` names the interpreter.
hapticd_write_program(hapticd-python "#!/bin/sh
# The Python interpreter the hapticd package was built for, with the package on its path (written by the build).
if [ \"\${1:-}\" = --which ]; then echo '${HAPTICD_PYTHON}'; exit 0; fi
here=\$(dirname \"\$(readlink -f \"\$0\")\")
PYTHONPATH=\"\$here/@HAPTICD_PACKAGE_REL@\${PYTHONPATH:+:\$PYTHONPATH}\" exec '${HAPTICD_PYTHON}' \"\$@\"
")
