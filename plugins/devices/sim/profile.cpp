#include "profile.hpp"

#include <stdexcept>

namespace hapticd::sim {

Profile::Kind Profile::parse(const std::string& name) {
  if (name == "constant") return Kind::kConstant;
  if (name == "step") return Kind::kStep;
  if (name == "ramp") return Kind::kRamp;
  if (name == "sine") return Kind::kSine;
  throw std::invalid_argument("profile '" + name + "': use constant, step, ramp or sine");
}

}  // namespace hapticd::sim
