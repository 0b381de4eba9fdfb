#include "profile.hpp"

#include <stdexcept>

namespace hapticd::sim {

Profile::Kind Profile::parse(const std::string& name) {
  if (name == "constant") return Kind::constant;
  if (name == "step") return Kind::step;
  if (name == "ramp") return Kind::ramp;
  if (name == "sine") return Kind::sine;
  throw std::invalid_argument("profile '" + name + "': use constant, step, ramp or sine");
}

}  // namespace hapticd::sim
