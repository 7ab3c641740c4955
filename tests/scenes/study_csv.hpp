// The values of a study's study.csv (one header line, one row: NAME, NAME_err, …) by
// name, for the study tests.
#pragma once
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace grainflow::scenes::test {

inline std::map<std::string, double> study_csv_values(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  std::stringstream h(header), r(row);
  std::map<std::string, double> out;
  for (std::string name, value; std::getline(h, name, ',') && std::getline(r, value, ',');) out[name] = std::stod(value);
  return out;
}

}  // namespace grainflow::scenes::test
