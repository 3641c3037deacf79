// The exact local solve of one contact in the non-linear Gauss-Seidel
// (Jean 1999, "The non-smooth contact dynamics method", CMAME 177, s. 4;
// Moreau 1994). Local frame (n, t1, t2); W the 3x3 Delassus block; the post-step
// relative velocity is u = w + W lambda, where w already holds the velocity bias of
// the gap: w_n = u_free_n + b with b the velocity that closes the gap in one step.
// Signorini: u_n >= 0, lambda_n >= 0, u_n lambda_n = 0.
// Coulomb:   |lambda_t| <= mu lambda_n; stick (u_t = 0) inside the cone,
//            slide with lambda_t = -mu lambda_n u_t / |u_t| on its surface.
#pragma once

#include "ratchet/core/types.hpp"

namespace ratchet {

enum class LocalStatus { Open, Stick, Slide };

struct LocalSolution {
  Vec3 lambda = Vec3::Zero();  // (lambda_n, lambda_t1, lambda_t2)
  LocalStatus status = LocalStatus::Open;
};

// Normal part only (frictionless contact, or mu = 0).
inline double solve_local_normal(double W_nn, double w_n) {
  return w_n >= 0.0 ? 0.0 : -w_n / W_nn;
}

// Full 3D Coulomb problem. mu = 0 reduces exactly to solve_local_normal.
LocalSolution solve_local_coulomb(const Mat3& W, const Vec3& w, double mu);

// The same with W^-1 given (the sweep computes it once per contact and step, not once
// per local solve).
LocalSolution solve_local_coulomb(const Mat3& W, const Mat3& W_inv, const Vec3& w, double mu);

}  // namespace ratchet
