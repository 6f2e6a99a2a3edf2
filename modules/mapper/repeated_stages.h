// The stages of report.json that PointlessMapper runs again (a re-adjustment after the
// verification, an adjustment with the joined images): the first round kept under a suffix.
#pragma once

#include <initializer_list>
#include <string>

#include "pgba/io/report.h"

namespace pgba {

// The stages of `names` kept under NAME + `suffix` (a stage done again).
void RenameStages(Report* report, std::initializer_list<const char*> names, const std::string& suffix);

// The stages of an adjustment that is done again, kept under "NAME_before_joining".
void KeepFirstAdjustmentStages(Report* report);

}  // namespace pgba
