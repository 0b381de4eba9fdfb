#include "hapticd/parameter_info.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

namespace hapticd {
namespace {

constexpr double kTunable = 1.0;
constexpr double kMinimumExclusive = 2.0;
constexpr std::size_t kHeader = 4;  // count, flags, minimum, maximum

std::string number_text(double v) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.10g", v);
  return buffer.data();
}

// Tabs and line ends inside a field would break the layout: they become spaces.
std::string field(std::string_view text) {
  std::string out(text);
  for (char& c : out)
    if (c == '\t' || c == '\n' || c == '\r') c = ' ';
  return out;
}

std::vector<std::string_view> split_tabs(std::string_view text) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t tab = text.find('\t', start);
    fields.push_back(text.substr(start, tab == std::string_view::npos ? std::string_view::npos : tab - start));
    if (tab == std::string_view::npos) return fields;
    start = tab + 1;
  }
}

std::optional<ParameterType> type_named(std::string_view name) {
  for (ParameterType t : {ParameterType::boolean, ParameterType::integer, ParameterType::real, ParameterType::string,
                          ParameterType::real_vector})
    if (to_string(t) == name) return t;
  return std::nullopt;
}

}  // namespace

std::string ParameterInfo::bounds_text() const {
  if (!minimum && !maximum) return "any";
  std::string out;
  if (minimum && maximum && !minimum_exclusive) return number_text(*minimum) + " to " + number_text(*maximum);
  if (minimum) out = (minimum_exclusive ? "> " : ">= ") + number_text(*minimum);
  if (maximum) out += (out.empty() ? "" : ", ") + std::string("<= ") + number_text(*maximum);
  return out;
}

RuntimeReply encode_parameter_info(const ParameterInfo& info, std::size_t count) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> values{static_cast<double>(count),
                             (info.tunable ? kTunable : 0.0) + (info.minimum_exclusive ? kMinimumExclusive : 0.0),
                             info.minimum.value_or(nan), info.maximum.value_or(nan)};
  values.insert(values.end(), info.value.begin(), info.value.end());
  std::string message = field(info.name) + '\t' + std::string(to_string(info.type)) + '\t' + field(info.unit) + '\t' +
                        field(info.value_text) + '\t' + field(info.description);
  return {true, std::move(message), std::move(values)};
}

std::optional<DescribedParameter> decode_parameter_info(std::string_view message, const std::vector<double>& values) {
  const std::vector<std::string_view> fields = split_tabs(message);
  if (fields.size() < 4 || values.size() < kHeader) return std::nullopt;
  const std::optional<ParameterType> type = type_named(fields[1]);
  const double count = values[0], flags = values[1];
  if (!type || !(count >= 1.0) || count != std::floor(count) || !(flags >= 0.0 && flags <= 3.0)) return std::nullopt;
  DescribedParameter d;
  d.count = static_cast<std::size_t>(count);
  ParameterInfo& p = d.info;
  p.name = fields[0];
  p.type = *type;
  p.unit = fields[2];
  p.value_text = fields[3];
  p.description = fields.size() > 4 ? fields[4] : std::string_view{};
  const auto bits = static_cast<int>(flags);
  p.tunable = (bits & 1) != 0;
  p.minimum_exclusive = (bits & 2) != 0;
  if (!std::isnan(values[2])) p.minimum = values[2];
  if (!std::isnan(values[3])) p.maximum = values[3];
  p.value.assign(values.begin() + kHeader, values.end());
  return d;
}

}  // namespace hapticd
