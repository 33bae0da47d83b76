// The HG-VAE subcommands besides `hgvae train` (cmd_hgvae.cc): each registers itself.
#pragma once

#include "commands.h"

namespace motionfork::app {

void AddHgvaeSampleCommand(CLI::App& hgvae, GlobalOptions& global);  // hgvae sample
void AddHgvaeEvalCommand(CLI::App& hgvae, GlobalOptions& global);    // hgvae eval
void AddImputeCommand(CLI::App& app, GlobalOptions& global);         // impute
void AddOodCommand(CLI::App& app, GlobalOptions& global);            // ood

}  // namespace motionfork::app
