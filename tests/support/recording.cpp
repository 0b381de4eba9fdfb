#include "support/recording.hpp"

#include <sstream>
#include <stdexcept>

#include "hapticd/recording/recording_export.hpp"

namespace hapticd::test {

std::map<std::string, std::string> recording_csv(const std::filesystem::path& file,
                                                 const std::vector<std::string>& exclude) {
  std::map<std::string, std::string> out;
  for (const std::string& d : recording::recorded_devices(file)) {
    std::ostringstream text;
    recording::export_csv(file, d, text, exclude);
    out[d] = text.str();
  }
  return out;
}

std::vector<double> recording_column(const std::string& csv, const std::string& name) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  int index = -1, k = 0;
  std::istringstream header(line);
  for (std::string cell; std::getline(header, cell, ','); ++k)
    if (index < 0 && (cell == name || (name.back() == '.' && cell.rfind(name, 0) == 0))) index = k;
  if (index < 0) throw std::invalid_argument("no column " + name);
  std::vector<double> values;
  while (std::getline(in, line)) {
    std::istringstream cells(line);
    std::string cell;
    for (int c = 0; c <= index; ++c) std::getline(cells, cell, ',');
    values.push_back(std::stod(cell));
  }
  return values;
}

}  // namespace hapticd::test
