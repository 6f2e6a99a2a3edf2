// Outputs kept apart from inputs: no command writes, links or deletes where an input lives.
//
// Every command that writes checks its output against the inputs it was given before it
// touches anything: an output that is an input, lies inside an input folder, or would
// replace an entry that holds an input is an InputError "OUTPUT: problem" naming both.
// (Converting a dataset into its own folder replaced each photo by a link to itself.)
// Paths are compared after resolving symbolic links and "..", so another spelling of the
// same folder is caught too.
#pragma once

#include <string>
#include <vector>

namespace pgba {

// An input as the user named it: the option (or role) and the path.
struct NamedInput {
  std::string option;  // "--images", "--cameras", ...
  std::string path;
};

// Checks the output folder `out`, of which the command writes or removes the entries
// `written` (names directly inside `out`, e.g. "images", "report.json"): InputError if `out`
// is an input or lies inside an input folder, or if an input is (or lies inside) one of the
// written entries. An input inside `out` under another name is fine (a workspace's own photo
// folder). Empty input paths are ignored.
void CheckOutputDirApartFromInputs(const std::string& out, const std::vector<std::string>& written,
                                   const std::vector<NamedInput>& inputs);

// The same for one output file: InputError if `out` is an input or lies inside an input
// folder.
void CheckOutputFileApartFromInputs(const std::string& out, const std::vector<NamedInput>& inputs);

// An empty output path is an InputError naming the option (it would write into the current
// folder).
void RequireOutputPath(const std::string& out, const std::string& option);

}  // namespace pgba
