// Errors that end a run with a clear one-line message.
//
// InputError is thrown for anything the user handed us that we cannot use (missing
// file, malformed line, NaN, unresolved id, unknown option value). The CLI catches it,
// prints "error: <what>" and exits with code 2. The message always names the file (and
// the line where there is one) so the user can go straight to the problem.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace pgba {

// An InputError names its file (`file()`, when thrown by ThrowInputError), or is a stage's
// finding about the data it was given ("tracks: no image pair could be verified"), which the
// command re-throws naming the file the data came from (NamingTheSource).
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what, std::string file = "")
      : std::runtime_error(what), file_(std::move(file)) {}
  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

// "FILE:LINE: problem" (LINE omitted when <= 0).
std::string FormatInputError(const std::string& file, int line, const std::string& problem);

[[noreturn]] void ThrowInputError(const std::string& file, int line, const std::string& problem);

// Runs `work`, whose data came from `source` (a tracks model's images.txt, a database, a
// folder of photos): an InputError naming no file is re-thrown as "SOURCE: problem" (a
// leading "tracks: " dropped, the source says it), so that every error names a file.
template <typename Work>
decltype(auto) NamingTheSource(const std::string& source, Work&& work) {
  try {
    return work();
  } catch (const InputError& e) {
    if (!e.file().empty()) throw;
    std::string problem = e.what();
    if (problem.rfind("tracks: ", 0) == 0) problem.erase(0, 8);
    ThrowInputError(source, 0, problem);
  }
}

// `text` as one line: control characters (a line break in a path the user gave, in a name
// read from a file) shown as \xNN, so that an error message is always exactly one line.
std::string OneLine(const std::string& text);

// Exit code used by the CLI for unusable input.
constexpr int kInputErrorExitCode = 2;

}  // namespace pgba
