// CSV of joint positions: one frame a row.
//
// Layout (what WriteCsvMotion writes and ReadCsvMotion expects):
//   # motionfork positions; fps=30; unit=m; skeleton=bandai      <- optional comment line(s)
//   Hips.x,Hips.y,Hips.z,UpperLeg_R.x,...                         <- header: 3 columns per joint
//   0.01,0.95,0.12,...                                            <- one row per frame, metres
// The header names the joints; ReadCsvMotion maps them to the given skeleton by name (any column
// order), or builds an anonymous skeleton from them when none is given.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/motion.h"

namespace motionfork {

// fps: used when the file has no "fps=" comment. Throws FormatError naming the file, line and
// column on a non-number, NaN/Inf, wrong column count, unknown or missing joint names. With
// `missing`, empty fields and nan/NaN are accepted as missing values: they read as 0 and are
// marked 1 in *missing ([T, J, 3]).
Motion ReadCsvMotion(const std::string& path, std::shared_ptr<const Skeleton> skeleton, double fps,
                     std::vector<uint8_t>* missing = nullptr);
// All-or-nothing write.
void WriteCsvMotion(const std::string& path, const Motion& motion);

}  // namespace motionfork
