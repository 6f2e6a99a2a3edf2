#include "apps/commands.h"
namespace pgba::app {
void RegisterSynth(CLI::App& app) {}
}
