// Catch2 in a test that also includes LibTorch. LibTorch pulls in glog, whose CHECK(cond) macro
// silently replaces Catch's CHECK when glog comes second (the checks then abort instead of being
// reported, and pass unseen). Include LibTorch first, drop glog's CHECK, then Catch.
#pragma once

#include <torch/torch.h>
#undef CHECK
#include <catch2/catch.hpp>
