#pragma once
// A parameter as a running device describes it (hapticctl params, get): the schema's declaration and the value
// in effect. It travels in a run-time reply (RuntimeReply, and ControlReply on DDS) in a fixed layout, so the
// server and every client read one definition:
//   message: "<stage>.<name>\t<type>\t<unit>\t<value>\t<description>" (the wire's text ends at 127 characters:
//            a long description is cut, nothing before it is)
//   values:  [count, flags, minimum, maximum, value...] - count: parameters the device has (describe requests
//            by index run 0 .. count-1); flags: 1 tunable at run time, 2 the minimum is exclusive; a bound the
//            schema does not give is NaN; the value's numbers (a boolean as 0 or 1, text as none) follow, as many
//            as the reply holds (the message's value text is the whole value).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/export.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/runtime_request.hpp"

namespace hapticd {

struct ParameterInfo {
  std::string name;  // "<stage>.<parameter>"
  ParameterType type = ParameterType::real;
  std::string unit;  // empty: dimensionless
  std::string description;
  bool tunable = false;  // settable while the device runs (a set request)
  std::optional<double> minimum;
  std::optional<double> maximum;
  bool minimum_exclusive = false;
  std::string value_text;     // the value in effect, as format_value writes it
  std::vector<double> value;  // its numbers (a boolean as 0 or 1; none for text)

  // "0 <= x <= 1", "> 0", "any" - the bounds as one phrase.
  [[nodiscard]] HAPTICD_API std::string bounds_text() const;
};

// The reply to a describe request: `info` of a device that has `count` parameters.
[[nodiscard]] HAPTICD_API RuntimeReply encode_parameter_info(const ParameterInfo& info, std::size_t count);

struct DescribedParameter {
  ParameterInfo info;
  std::size_t count = 0;  // the parameters the device has
};
// A describe reply read back; nullopt when it does not have the layout above.
[[nodiscard]] HAPTICD_API std::optional<DescribedParameter> decode_parameter_info(std::string_view message,
                                                                                  const std::vector<double>& values);

}  // namespace hapticd
