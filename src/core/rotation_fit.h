// The rotation that best turns one set of directions onto another: Kabsch's least-squares fit
// for two or more, the shortest turn for one.
#pragma once

#include <vector>

namespace motionfork {

// Row-major 3x3 proper rotation R minimising sum_i w_i |R u_i - v_i|^2 over pairs of 3-vectors
// (u, v: [n, 3]; w: [n] or empty for 1). One pair: the shortest turn of u's direction onto v's
// (the identity when either is zero). With collinear directions the turn about their line is the
// least one that fits.
void FitRotation(const std::vector<double>& u, const std::vector<double>& v,
                 const std::vector<double>& w, double* r);

}  // namespace motionfork
