// What `motionfork prior train` prints: which epochs get a line, and the end-of-run warning.
#include "pipeline/prior_training_text.h"

#include <catch2/catch.hpp>

namespace motionfork::pipeline {
namespace {

TEST_CASE("a long prior run prints about a hundred epoch lines with the first and the last") {
  int lines = 0;
  for (int e = 0; e < 80; ++e) lines += PriorEpochGetsLine(e, 80);
  CHECK(lines == 80);  // a short run: every epoch

  lines = 0;
  for (int e = 0; e < 1500; ++e) lines += PriorEpochGetsLine(e, 1500);
  CHECK(lines == 101);  // every 15th (15, 30, ..., 1500) and the first
  CHECK(lines <= kPriorEpochLines + 1);
  CHECK(PriorEpochGetsLine(0, 1500));
  CHECK(PriorEpochGetsLine(1499, 1500));
  CHECK_FALSE(PriorEpochGetsLine(1, 1500));

  lines = 0;
  for (int e = 0; e < 215; ++e) lines += PriorEpochGetsLine(e, 215);
  CHECK((lines >= 70 && lines <= kPriorEpochLines + 2));
  CHECK(PriorEpochGetsLine(214, 215));
}

TEST_CASE("the done text warns when the held-out NLL was still falling and only then") {
  PriorTrainingRun run;
  run.completed = true;
  run.summary.held_out_nll = {3, 2, 1};
  run.outcome.completed = true;
  CHECK(PriorTrainingDoneText(run, "out").find("warning") == std::string::npos);
  run.outcome.still_falling = true;
  run.outcome.recent_gain = 0.75;
  const std::string text = PriorTrainingDoneText(run, "out");
  CHECK(text.find("warning:   the held-out NLL was still falling (0.75 nats") != std::string::npos);
  CHECK(text.find("bundle:    out") != std::string::npos);
}

}  // namespace
}  // namespace motionfork::pipeline
