// What `motionfork train --epochs N` does to a config's schedule.
#include "generator/training/training_setup.h"

#include <catch2/catch.hpp>
#include <stdexcept>

using namespace motionfork;

namespace {

TrainingOptions Schedule(int epochs, int constant) {
  TrainingOptions t;
  t.epochs = epochs;
  t.lr_constant_epochs = constant;
  return t;
}

}  // namespace

TEST_CASE("train --epochs scales the constant learning-rate phase, so a cut recipe still decays") {
  TrainingOptions t = Schedule(120, 60);  // the Bandai recipe
  OverrideEpochs(&t, 40);
  CHECK(t.epochs == 40);
  CHECK(t.lr_constant_epochs == 20);
  OverrideEpochs(&t, 120);  // resumed longer: the config's own schedule again
  CHECK(t.lr_constant_epochs == 60);

  t = Schedule(2, 1);
  OverrideEpochs(&t, 3);  // 1.5 rounds to 2
  CHECK(t.lr_constant_epochs == 2);
  t = Schedule(10, 0);  // decaying from the start stays so
  OverrideEpochs(&t, 7);
  CHECK(t.lr_constant_epochs == 0);
  t = Schedule(10, 10);  // never decaying stays so
  OverrideEpochs(&t, 25);
  CHECK(t.lr_constant_epochs == 25);
  CHECK_THROWS_AS(OverrideEpochs(&t, 0), std::invalid_argument);
}
