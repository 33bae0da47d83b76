// The flags every subcommand that reads a motion file shares: --skeleton, --fps, --joint-map,
// --bvh-scale
// (reading itself is pipeline/motion_input.h).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "commands.h"
#include "pipeline/motion_input.h"

namespace motionfork::app {

using pipeline::LoadedMotion;
using pipeline::MotionInputOptions;
using pipeline::MotionWithGaps;

void AddMotionInputOptions(CLI::App* cmd, MotionInputOptions* o);

// The options as parsed, with the configs folder that --skeleton names are looked up in.
MotionInputOptions WithConfigDir(MotionInputOptions o, const std::string& config_dir);

// The motion file on a model's skeleton and at its frame rate (pipeline::LoadMotionWithGaps;
// --skeleton names looked up in the configs folder), with its mapping notes and NoteResampling's
// note; masks as --mask
// gives them (random ones drawn from the seed).
// protocol: the model's (its `up` is the frame the motion is turned into).
MotionWithGaps LoadMotionForModel(const std::string& path, const MotionInputOptions& input,
                                  const GlobalOptions& global, const Skeleton& skeleton, double fps,
                                  const std::string& protocol,
                                  const std::vector<std::string>& masks = {}, uint64_t seed = 0);

// Prints how a motion was read (pipeline::InputNoteLine per note) on stderr.
void PrintInputNotes(const std::string& path, const std::vector<std::string>& notes);

// Prints "note: resampling PATH from A Hz to the model's B Hz" on stderr when the motion was
// resampled on the way in (from_fps > 0).
void NoteResampling(const std::string& path, double from_fps, double to_fps);

}  // namespace motionfork::app
