#include "core/text_format.h"

#include <catch2/catch.hpp>
#include <string>

namespace motionfork {

TEST_CASE("StringPrintf formats like printf, longer than any fixed buffer") {
  CHECK(StringPrintf("%d frames at %.3g Hz", 120, 30.0) == "120 frames at 30 Hz");
  const std::string wide(5000, 'x');
  CHECK(StringPrintf("[%s]", wide.c_str()) == "[" + wide + "]");
  CHECK(StringPrintf("%s", "").empty());
}

TEST_CASE("StringAppendf appends to what is there") {
  std::string s = "epoch 1";
  StringAppendf(&s, ": loss %.2f", 0.125);
  StringAppendf(&s, "%s", "");
  CHECK(s == "epoch 1: loss 0.12");
}

TEST_CASE("WithThousands and Duration") {
  CHECK(WithThousands(0) == "0");
  CHECK(WithThousands(999) == "999");
  CHECK(WithThousands(1234567) == "1,234,567");
  CHECK(WithThousands(-1000) == "-1,000");
  CHECK(Duration(12.34) == "12.3 s");
  CHECK(Duration(245) == "4 min 05 s");
  CHECK(Duration(3720) == "1 h 02 min");
}

}  // namespace motionfork
