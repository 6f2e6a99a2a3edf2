#include "pgba/io/json_file_reader.h"

#include <cmath>
#include <set>
#include <vector>

#include "pgba/util/error.h"
#include "pgba/util/input_file.h"

namespace pgba {

using nlohmann::json;

namespace {

// nlohmann reports a byte offset; users want a line and a column.
void LineColumn(const std::string& text, size_t byte, int* line, int* column) {
  *line = 1;
  *column = 1;
  for (size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++*line;
      *column = 1;
    } else {
      ++*column;
    }
  }
}

// The keys seen so far in each open object (empty for arrays), for the duplicate check.
struct OpenContainer {
  std::set<std::string> keys;
  std::string key;  // the current key, for the dotted path in the message
};

std::string KeyPath(const std::vector<OpenContainer>& open) {
  std::string path;
  for (const OpenContainer& c : open)
    if (!c.key.empty()) path += (path.empty() ? "" : ".") + c.key;
  return path;
}

}  // namespace

json ParseJsonStrictly(const std::string& text, const std::string& origin) {
  std::vector<OpenContainer> open;
  const json::parser_callback_t reject_duplicates = [&](int, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        open.emplace_back();
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!open.empty()) open.pop_back();
        break;
      case json::parse_event_t::key:
        if (!open.empty()) {
          open.back().key = parsed.get<std::string>();
          if (!open.back().keys.insert(open.back().key).second)
            ThrowInputError(origin, 0, "duplicate key '" + KeyPath(open) + "'");
        }
        break;
      case json::parse_event_t::value:
        break;
    }
    return true;
  };
  try {
    return json::parse(text, reject_duplicates);
  } catch (const json::parse_error& e) {
    // e.byte is one past the offending character.
    int line, column;
    LineColumn(text, e.byte > 0 ? e.byte - 1 : 0, &line, &column);
    std::string what = e.what();
    const size_t colon = what.find(": ");  // drop "[json.exception.parse_error.101] parse error at ...:"
    if (colon != std::string::npos) what = what.substr(colon + 2);
    ThrowInputError(origin, line, "malformed JSON at column " + std::to_string(column) + ": " + what);
  } catch (const json::exception& e) {
    // out_of_range.406 "number overflow parsing '1e999'" carries no position.
    std::string what = e.what();
    const size_t bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    ThrowInputError(origin, 0, "malformed JSON: " + what);
  }
}

void JsonFileReader::Fail(const std::string& where, const std::string& problem) const {
  ThrowInputError(path_, 0, where.empty() ? problem : where + ": " + problem);
}

json JsonFileReader::Parse() const { return ParseJsonStrictly(ReadRegularFile(path_), path_); }

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
