#include "apps/commands.h"
namespace pgba::app {
void RegisterMatch(CLI::App& app) {}
}  // namespace pgba::app
