// Include this instead of <catch2/catch.hpp> in tests that use LibTorch. LibTorch brings glog,
// whose CHECK(cond) macro replaces Catch's when glog is included second: failed checks would then
// abort instead of being reported. LibTorch first, glog's CHECK dropped, then Catch.
#pragma once

#include <torch/torch.h>
#undef CHECK
#include <catch2/catch.hpp>
