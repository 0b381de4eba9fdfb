#pragma once
// The parameters a session file would give a plugin, for testing it outside the server: the schema's defaults,
// then the values given, each checked against its declaration as the server checks a session file's (a
// ParameterError names the key). A required parameter not given is an error, as it is in a session file.
//
//   auto p = hapticd::testing::parameters_of(MyModel::parameter_schema(), {{"mass_kg", 2.0}});
//   model.configure(p, context);
#include <initializer_list>
#include <string>
#include <utility>

#include "hapticd/parameters.hpp"

namespace hapticd::testing {

inline Parameters parameters_of(const ParameterSchema& schema,
                                std::initializer_list<std::pair<std::string, ParameterValue>> values = {}) {
  Parameters p;
  for (const auto& [name, value] : values) {
    const ParameterSpec* spec = schema.find(name);
    if (spec == nullptr) throw ParameterError(name, "the schema declares no parameter '" + name + "'");
    spec->check(value);
    p.set(name, value, "test");
  }
  for (const ParameterSpec& spec : schema.specs()) {
    if (p.has(spec.name)) continue;
    if (!spec.default_value) throw ParameterError(spec.name, "required, and not given");
    p.set(spec.name, *spec.default_value);
  }
  return p;
}

}  // namespace hapticd::testing
