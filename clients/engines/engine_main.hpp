#pragma once
// The shipped engines' main(): every error ends with a message on standard error and exit code 2, never an abort -
// a DDS participant that cannot be made (a malformed HAPTICD_DDS_NETWORK, a Cyclone configuration or DDS Security
// refusing it), a bad client id, a scene that does not load.
#include <cstdio>
#include <exception>

namespace hapticd::examples {

inline int guarded_main(const char* program, int (*run)(int, char**), int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", program, e.what());
    return 2;
  }
}

}  // namespace hapticd::examples
