// The exact local solve of one contact in the non-linear Gauss-Seidel
// (Jean 1999, "The non-smooth contact dynamics method", CMAME 177, s. 4;
// Moreau 1994). Local frame (n, t1, t2); W the 3x3 Delassus block; the post-step
// relative velocity is u = w + W lambda, where w already holds the velocity bias of
// the gap: w_n = u_free_n + b with b the velocity that closes the gap in one step.
// Signorini: u_n >= 0, lambda_n >= 0, u_n lambda_n = 0.
// Coulomb:   |lambda_t| <= mu lambda_n; stick (u_t = 0) inside the cone,
//            slide with lambda_t = -mu lambda_n u_t / |u_t| on its surface.
#pragma once

#include <algorithm>
#include <cmath>

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

namespace detail {
// The sliding branch of solve_local_coulomb below, not an entry point: w[0] < 0, mu > 0,
// and the stick impulse (stick = -W^-1 w, lt its tangential norm) lies outside the cone.
// hint: a unit direction to start Newton from (the contact's last slide), or null.
// It is slide_from_hint, and where that fails or there is no hint, slide_cold.
// max_steps > 0: an inexact slide from the hint (slide_from_hint).
LocalSolution solve_local_slide(const Mat3& W, const Vec3& w, double mu, const Vec3& stick, double lt,
                                const Eigen::Vector2d* hint = nullptr, int max_steps = 0);
// Newton from the hint alone: true, with the impulse, when it ends at an admissible slide.
// max_steps > 0 (solver.slide_newton_steps): at most that many steps, and a direction the
// budget cut short counts when the slide is against it (lambda_n >= 0, u_t . d < 0): an
// impulse on the cone, the next sweep's start. At a fixed point of the sweeps the hint is
// the answer and its Newton step zero, so the converged answer is the exact law's
// (Acary, Bremond & Huber 2018, INRIA RR-9118: inexact local solves in the Gauss-Seidel).
bool slide_from_hint(const Mat3& W, const Vec3& w, double mu, const Eigen::Vector2d& hint, Vec3& lambda,
                     int max_steps = 0);
// The same for n (1 to kSlideLanes) independent problems at once, each with the bits it
// has alone: their Newton iterations interleaved, so that one's divisions and square
// roots run while the others' wait (a slide is a chain of them, and a third of a sweep's
// rows slide).
constexpr int kSlideLanes = 4;
void slide_from_hints(int n, const Mat3* const W[], const Vec3* const w[], const double mu[],
                      const Eigen::Vector2d* const hint[], Vec3* lambda[], bool found[],
                      const int max_steps[] = nullptr);  // per lane, as slide_from_hint's; null: all exact
// The slide without a hint, in three stages that can be taken apart (a sweep solves the
// second stage of several rows together): the fixed point from the stick direction d0
// (slide_fixed_point: true with the impulse when it converged), Newton from d0
// (slide_from_hint), and the scan of the angle for an admissible root (slide_scan).
LocalSolution slide_cold(const Mat3& W, const Vec3& w, double mu, const Vec3& stick, double lt);
bool slide_fixed_point(const Mat3& W, const Vec3& w, double mu, const Vec3& stick, double lt, Eigen::Vector2d& d0,
                       Vec3& lambda);
Vec3 slide_scan(const Mat3& W, const Vec3& w, double mu, const Vec3& stick, const Eigen::Vector2d& d0);
}  // namespace detail

// What solve_local_coulomb decides before a slide: the open, frictionless and stick
// cases (true, with sol), or that the contact slides (false, with the stick impulse and
// its tangential norm, which the slide starts from).
inline bool solve_local_before_slide(const Mat3& W, const Mat3& W_inv, const Vec3& w, double mu, double shift,
                                     LocalSolution& sol, Vec3& stick, double& lt) {
  if (w[0] >= 0.0) return true;  // the gap stays open with no impulse
  if (mu == 0.0) {
    sol.lambda = Vec3(solve_local_normal(shift != 0.0 ? W(0, 0) + shift : W(0, 0), w[0]), 0.0, 0.0);
    sol.status = LocalStatus::Slide;
    return true;
  }
  // Stick: u = 0.
  stick = -(W_inv * w);
  lt = std::sqrt(stick[1] * stick[1] + stick[2] * stick[2]);  // no overflow: impulses are O(1)
  if (stick[0] > 0.0 && lt <= mu * stick[0]) {
    sol.lambda = stick;
    sol.status = LocalStatus::Stick;
    return true;
  }
  return false;
}

// W + shift I (the compliant law's block), formed only for a slide.
inline Mat3 shifted_block(const Mat3& W, double shift) {
  Mat3 shifted = W;
  shifted.diagonal().array() += shift;
  return shifted;
}

// The same with W^-1 given (the sweep computes it once per contact and step, not once
// per local solve). Inline: the open and stick branches are 92 % of the local solves
// of a settled bed and a few products each, and the call and its returned struct cost
// about 20 of their 150 instructions (callgrind, docs/performance.md); only the slide
// is out of line. shift != 0: the block is W + shift I (the compliant law, docs/method.md
// s. 5) and W_inv its inverse; W + shift I is formed only for a slide, which alone needs
// more of it than its diagonal's first entry.
inline LocalSolution solve_local_coulomb(const Mat3& W, const Mat3& W_inv, const Vec3& w, double mu,
                                         const Eigen::Vector2d* slide_hint = nullptr, double shift = 0.0) {
  LocalSolution sol;
  Vec3 stick;
  double lt = 0.0;
  if (solve_local_before_slide(W, W_inv, w, mu, shift, sol, stick, lt)) return sol;
  if (shift == 0.0) return detail::solve_local_slide(W, w, mu, stick, lt, slide_hint);
  return detail::solve_local_slide(shifted_block(W, shift), w, mu, stick, lt, slide_hint);
}

// The nearest point of the cone lambda_n >= 0, |lambda_t| <= mu lambda_n along lambda_t
// (the normal clipped at 0, the tangential part scaled down).
inline Vec3 project_onto_cone(Vec3 l, double mu) {
  l[0] = l[0] > 0.0 ? l[0] : 0.0;
  const double lt = std::sqrt(l[1] * l[1] + l[2] * l[2]), cap = mu * l[0];
  if (lt > cap) {
    const double f = lt > 0.0 ? cap / lt : 0.0;
    l[1] *= f;
    l[2] *= f;
  }
  return l;
}

// The warm start's clip of a kept impulse onto the cone (World::warm_start): the clip of
// project_onto_cone, with |lambda_t| taken by hypot and a tangent of +0 at a zero cap.
// Not project_onto_cone because the two round differently (hypot against sqrt of the
// sum of squares, and the sign of a zero tangent): one function would move the last bit
// of a clipped impulse, and so every warm-started run and the golden data, for no
// physical difference.
inline Vec3 clip_kept_impulse(Vec3 l, double mu) {
  l[0] = std::max(0.0, l[0]);
  const double lt = std::hypot(l[1], l[2]), cap = mu * l[0];
  if (lt > cap) {
    l[1] *= cap / lt;
    l[2] *= cap / lt;
  }
  if (cap == 0.0) {
    l[1] = 0.0;
    l[2] = 0.0;
  }
  return l;
}

// The direction a contact with impulse lambda slides in, if it lies on its cone
// (|lambda_t| = mu lambda_n to round-off): the Newton start for its next solve.
inline bool slide_direction(const Vec3& lambda, double mu, Eigen::Vector2d& d) {
  const double lt = std::sqrt(lambda[1] * lambda[1] + lambda[2] * lambda[2]);
  constexpr double kOnCone = 1.0 - 1e-9;  // |lambda_t| / (mu lambda_n): on the surface to round-off
  if (!(lambda[0] > 0.0) || !(lt > 0.0) || lt < kOnCone * mu * lambda[0]) return false;
  d = Eigen::Vector2d(lambda[1] / lt, lambda[2] / lt);
  return true;
}

}  // namespace ratchet
