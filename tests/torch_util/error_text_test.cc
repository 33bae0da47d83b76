// What a user reads for an exception that reaches the command.
#include "torch_util/error_text.h"

#include <torch/torch.h>

#include <catch2/catch.hpp>
#include <new>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace motionfork {
namespace {

using Catch::Contains;

TEST_CASE("error text: LibTorch, out of memory and JSON errors become one readable line") {
  try {
    (void)torch::empty({-1});
    FAIL("expected a LibTorch error");
  } catch (const std::exception& e) {
    const std::string m = UserErrorMessage(e, "running 'motionfork predict'");
    CHECK_THAT(m, Contains("LibTorch: ") && Contains("negative dimension"));
    CHECK_THAT(m, !Contains("frame #") && !Contains("\n"));
  }
  CHECK(UserErrorMessage(std::bad_alloc(), "running 'motionfork predict'") ==
        "out of memory while running 'motionfork predict' (the input or the request needs more "
        "memory than is available)");
  try {
    const auto parsed = nlohmann::json::parse("{1}");
    FAIL("expected a JSON error, parsed " << parsed.dump());
  } catch (const std::exception& e) {
    const std::string m = UserErrorMessage(e, "");
    CHECK_THAT(m, Contains("JSON: ") && !Contains("[json.exception"));
  }
  CHECK(UserErrorMessage(std::invalid_argument("walk.csv: expected x"), "") ==
        "walk.csv: expected x");
}

}  // namespace
}  // namespace motionfork
