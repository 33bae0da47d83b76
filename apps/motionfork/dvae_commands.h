// The Motion-DVAE subcommands: `dvae train|finetune` (cmd_dvae.cc) and `denoise` (cmd_denoise.cc).
#pragma once

#include "commands.h"

namespace motionfork::app {

void AddDvaeCommand(CLI::App& app, GlobalOptions& global);       // dvae train|finetune
void AddDenoiseCommand(CLI::App& app, GlobalOptions& global);    // denoise
void AddDvaeEvalCommand(CLI::App& dvae, GlobalOptions& global);  // dvae eval

}  // namespace motionfork::app
