// One register of a constraint set's vector program (constraint_set.h: VectorOp) for one frame,
// shared by the angle checker and the training penalty's fused kernel: x, y, z and the squared
// length into out[0..3], and whether the register is undefined. Every comparison is written as
// !(a > b) so that NaN input counts as undefined instead of leaking out.
#pragma once

namespace motionfork {

// A bone: joint `to` minus joint `from` of a frame [J, 3]; undefined when its squared length is not
// above min_len2.
template <typename T, typename Index>
inline bool BoneRegister(const T* frame, Index from, Index to, T min_len2, T* out) {
  const T* p = frame + 3 * from;
  const T* q = frame + 3 * to;
  out[0] = q[0] - p[0];
  out[1] = q[1] - p[1];
  out[2] = q[2] - p[2];
  out[3] = out[0] * out[0] + out[1] * out[1] + out[2] * out[2];
  return !(out[3] > min_len2);
}

// A normal: u x v of two registers; undefined when either is, or when the vectors are so near
// parallel that the squared sine between them is not above min_sin2.
template <typename T>
inline bool CrossRegister(const T* u, const T* v, bool operand_undefined, T min_sin2, T* out) {
  out[0] = u[1] * v[2] - u[2] * v[1];
  out[1] = u[2] * v[0] - u[0] * v[2];
  out[2] = u[0] * v[1] - u[1] * v[0];
  out[3] = out[0] * out[0] + out[1] * out[1] + out[2] * out[2];
  return operand_undefined || !(out[3] > min_sin2 * u[3] * v[3]);
}

}  // namespace motionfork
