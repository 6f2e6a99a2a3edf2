#include "pgba/io/json_file_reader.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "pgba/util/error.h"

namespace pgba {

using nlohmann::json;

void JsonFileReader::Fail(const std::string& where, const std::string& problem) const {
  ThrowInputError(path_, 0, where.empty() ? problem : where + ": " + problem);
}

json JsonFileReader::Parse() const {
  std::ifstream in(path_, std::ios::binary);
  if (!in) Fail("", "cannot open");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    const size_t byte = std::min<size_t>(e.byte, text.size());
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + byte, '\n'));
    ThrowInputError(path_, line, "invalid JSON");
  }
}

const json& JsonFileReader::Field(const json& j, const char* key, const std::string& where) const {
  if (!j.is_object() || !j.contains(key)) Fail(where, std::string("missing \"") + key + "\"");
  return j.at(key);
}

double JsonFileReader::Number(const json& j, const std::string& where) const {
  if (!j.is_number() || !std::isfinite(j.get<double>())) Fail(where, "expected a finite number, got " + j.dump());
  return j.get<double>();
}

int64_t JsonFileReader::Integer(const json& j, const std::string& where) const {
  if (!j.is_number_integer()) Fail(where, "expected an integer, got " + j.dump());
  return j.get<int64_t>();
}

}  // namespace pgba
