#include "apps/commands.h"
namespace pgba::app {
void RegisterEvaluate(CLI::App& app) {}
}
