// Phase 4, first half: from the step's contact list to the solver's rows (local
// frames, Delassus blocks, expansion velocities, gap biases) and their warm start.
// docs/method.md s. 4-5, 9.
#include <algorithm>
#include <cmath>
#include <tuple>

#include "ratchet/solver/local_coulomb.hpp"
#include "ratchet/world/test_hooks.hpp"
#include "ratchet/world/thread_share.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

namespace {

// Skew-symmetric cross-product matrix [r]x.
Mat3 skew(const Vec3& r) {
  Mat3 m;
  m << 0.0, -r.z(), r.y(), r.z(), 0.0, -r.x(), -r.y(), r.x(), 0.0;
  return m;
}

// Tangent frame (t1, t2) of a unit normal n, deterministic: cross with the first axis
// least aligned with n.
void tangent_frame(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 axis = std::abs(n.x()) < 0.57735 ? Vec3::UnitX() : (std::abs(n.y()) < 0.57735 ? Vec3::UnitY() : Vec3::UnitZ());
  t1 = n.cross(axis).normalized();
  t2 = n.cross(t1);
}

}  // namespace

// Local frames, Delassus blocks W = H^T M^-1 H (Jean 1999, eq. 40), expansion
// velocities and the gap bias of every contact.
void World::build_rows() {
  StepScratch& s = scratch_;
  const double h = scene_.dt;
  const double p_gap = scene_.solver.p_gap;
  // Energy-safe relaxation (docs/method.md s. 5): the separation speed an overlap asks
  // for is at most sqrt(2 g* max(delta, margin)), g* the gravity's magnitude (1, the
  // scene's unit acceleration, without gravity).
  const double g_star = scene_.effects.gravity && scene_.gravity.norm() > 0.0 ? scene_.gravity.norm() : 1.0;
  const double margin = scene_.solver.contact_margin;
  const Vec3& c0 = scene_.container.scale_center;
  // The wall's expansion rate in the contact velocity; the planted-regression seam can
  // drop it (world/test_hooks.hpp).
  const double eps_wall = test_hooks().drop_wall_expansion ? 0.0 : scratch_.eps_c;
  s.rows.resize(s.contacts.size());
  double min_gap = 0.0;
  const int n = static_cast<int>(s.contacts.size());
  // Each row from its own contact: any split among threads gives the same rows (min is exact).
  const int parallel_min = parallel_min_rows();
#pragma omp parallel for schedule(static) reduction(min : min_gap) if (n > parallel_min)
  for (int k = 0; k < n; ++k) {
    SolverContact& c = s.contacts[static_cast<std::size_t>(k)];
    SolverRow& r = s.rows[static_cast<std::size_t>(k)];
    r.a = c.a;
    r.b = c.b;
    r.mu = c.mu;
    const Vec3& n = c.geometry.normal;
    const Vec3& p = c.geometry.point;
    c.ra = p - state_.x[c.a];
    Mat3 K = s.inv_mass[c.a] * Mat3::Identity() - skew(c.ra) * s.inv_inertia[c.a] * skew(c.ra);
    // A material point at lever r from a particle centre moves with eps_p r; a wall
    // point x with eps_c (x - c0) (docs/method.md s. 2). Fixed bodies keep scale 1, so
    // they have no expansion velocity.
    auto eps_of = [&](int body) { return scene_.bodies[static_cast<std::size_t>(body)].fixed ? 0.0 : scratch_.eps_p; };
    c.u_expansion = eps_of(c.a) * c.ra;
    if (!is_wall(c.b)) {
      c.rb = p - state_.x[c.b];
      K += s.inv_mass[c.b] * Mat3::Identity() - skew(c.rb) * s.inv_inertia[c.b] * skew(c.rb);
      c.u_expansion -= eps_of(c.b) * c.rb;
    } else if (scene_.container.walls[static_cast<std::size_t>(wall_index(c.b))].expands) {
      c.u_expansion -= eps_wall * (p - c0);
    }
    // Columns computed one by one with the same expressions in the frictionless and
    // the frictional case, so that mu = 0 reproduces friction-off bit for bit.
    const Vec3 Kn = K * n;
    r.W.setZero();
    r.W(0, 0) = n.dot(Kn);
    if (friction_on_) {
      tangent_frame(n, c.t1, c.t2);
      const Vec3 Kt1 = K * c.t1, Kt2 = K * c.t2;
      r.W(1, 0) = c.t1.dot(Kn); r.W(2, 0) = c.t2.dot(Kn);
      r.W(0, 1) = n.dot(Kt1);   r.W(1, 1) = c.t1.dot(Kt1); r.W(2, 1) = c.t2.dot(Kt1);
      r.W(0, 2) = n.dot(Kt2);   r.W(1, 2) = c.t1.dot(Kt2); r.W(2, 2) = c.t2.dot(Kt2);
    }
    r.F.col(0) = n;
    r.F.col(1) = c.t1;
    r.F.col(2) = c.t2;
    r.Ja.setZero();
    r.Jb.setZero();
    if (rotation_on_) {
      for (int j = 0; j < 3; ++j) {
        r.Ja.row(j) = c.ra.cross(r.F.col(j)).transpose();
        if (!is_wall(c.b)) r.Jb.row(j) = c.rb.cross(r.F.col(j)).transpose();
      }
    }
    // Compliance relative to the contact's own Delassus diagonal, as MuJoCo's
    // regularizer R = (1 - d)/d diag(A) (Todorov 2014; docs/method.md s. 5).
    const double compliance = row_compliance(r, scene_.solver.compliance);
    r.W_inv.setZero();
    if (friction_on_) {
      Mat3 Wc = r.W;
      Wc.diagonal().array() += compliance;
      r.W_inv = Wc.inverse();
    }
    r.u0 = r.F.transpose() * c.u_expansion;
    // Gap relaxation (docs/method.md s. 5): an overlap closes at p_gap g / h per step.
    const double g = c.geometry.gap;
    min_gap = std::min(min_gap, g);
    // Velocity-level Signorini: u_n(t+h) >= -g_eff / h. Theta enters the position update
    // only; a gap-based bias with theta < 1 would turn an inelastic landing into a rebound.
    r.bias_capped = 0.0;
    if (g >= 0.0) {
      r.bias = g / h;
    } else {
      // The speed stays in the bodies after the overlap is gone: capped, the energy one
      // correction adds is at most m g* max(delta, margin) for any h. A compliant row
      // keeps its bias, the spring's rest point, and gets the cap as a second law that
      // the solve applies where it pushes less (solver/nsgs.cpp).
      const double speed = p_gap * -g / h;
      const double cap = std::sqrt(2.0 * g_star * std::max(-g, margin));
      const bool capped = speed > cap;
      r.bias = -(capped && compliance == 0.0 ? cap : speed);
      r.bias_capped = capped && compliance > 0.0 ? -cap : 0.0;
    }
    r.lambda.setZero();
    r.law_taken = r.law_kept = 0;
    c.lambda.setZero();
  }
  stats_.max_overlap = min_gap < 0.0 ? -min_gap : 0.0;  // not -0
}

// Impulses of the previous step for the same (bodies, features), projected onto the
// new frame, clipped to the friction cone and applied before the first sweep, in the
// contacts' (colour) order. The groups of a colour share no moving body, so threads split
// them as the sweep does: every body gets its impulses in the same order, the same bits
// for any thread count. They are looked up in the order gathered (find_kept_impulses).
void World::warm_start(SolverBodies& bodies) {
  if (!scene_.solver.warm_start || state_.impulses.empty()) return;
  StepScratch& s = scratch_;
  const bool spring = friction_on_ && scene_.solver.compliance > 0.0 &&
                      scene_.solver.tangential_law == TangentialLaw::Spring;
  find_kept_impulses();
  const BodyArrays B = arrays_of(bodies);
  auto start = [&](int k) {
    const std::size_t j = static_cast<std::size_t>(k);
    const int found = s.kept_impulse[static_cast<std::size_t>(s.order[j])];
    if (found < 0) return;
    const SolverContact& c = s.contacts[j];
    const Vec3& P = state_.impulses[static_cast<std::size_t>(found)].impulse;
    const Vec3 lambda = friction_on_
                            ? clip_kept_impulse(Vec3(c.geometry.normal.dot(P), c.t1.dot(P), c.t2.dot(P)), c.mu)
                            : Vec3(std::max(0.0, c.geometry.normal.dot(P)), 0.0, 0.0);
    s.rows[j].lambda = lambda;
    // The spring law: the local law on u + c (lambda - lambda_kept), so a sticking contact
    // that keeps its load keeps its place (docs/method.md s. 5, Tangential law).
    if (spring) {
      const double c_row = row_compliance(s.rows[j], scene_.solver.compliance);
      s.rows[j].u0[1] -= c_row * lambda[1];
      s.rows[j].u0[2] -= c_row * lambda[2];
    }
    apply_local_impulse(s.rows[j], lambda, B, rotation_on_);
  };
  const RowColouring& col = s.colouring;
  const int* gb = col.group_begin.data();
  const int* cb = col.colour_begin.data();
  const int nc = col.colours(), n = static_cast<int>(s.contacts.size());
  const int parallel_min = parallel_min_rows();
#pragma omp parallel if (n > parallel_min)
  for (int colour = 0; colour < nc; ++colour) {
#pragma omp for schedule(static)
    for (int grp = cb[colour]; grp < cb[colour + 1]; ++grp)
      for (int k = gb[grp]; k < gb[grp + 1]; ++k) start(k);
  }
}

// Per contact as gathered, its kept impulse (index into the sorted State::impulses) or -1:
// the first with its key, as a binary search would find it. Gathered body pairs come in
// ascending (a, b), so one pointer walks the impulses alongside; wall contacts come body
// by body (each body's walls in descending b), so a second pointer finds each body's
// first impulse and its few wall impulses are scanned. Each thread walks its own share
// of the gathered contacts, its pointers started by a binary search at the share's first
// body: the answer is a function of the key alone, the same for any split.
void World::find_kept_impulses() {
  StepScratch& s = scratch_;
  const std::vector<KeptImpulse>& kept = state_.impulses;
  const int n = static_cast<int>(s.row_a.size());
  const std::size_t nk = kept.size();
  s.kept_impulse.assign(static_cast<std::size_t>(n), -1);
  std::vector<int> contact_of(static_cast<std::size_t>(n));  // gathered index -> its place in the colour order
  // The body pairs' contacts come before the walls'.
  const int pair_rows = static_cast<int>(
      std::partition_point(s.row_b.begin(), s.row_b.end(), [](int b) { return !is_wall(b); }) - s.row_b.begin());
  auto key_of = [&](int g) {
    const std::size_t k = static_cast<std::size_t>(g);
    const ContactPoint& p = s.contacts[static_cast<std::size_t>(contact_of[k])].geometry;
    return ContactKey{s.row_a[k], s.row_b[k], p.feature_a, p.feature_b};
  };
  auto first_of_body = [&](int body) {
    return static_cast<std::size_t>(
        std::partition_point(kept.begin(), kept.end(), [&](const KeptImpulse& k) { return k.key.a < body; }) -
        kept.begin());
  };
  const int parallel_min = parallel_min_rows();
#pragma omp parallel if (n > parallel_min)
  {
#pragma omp for schedule(static)
    for (int j = 0; j < n; ++j) contact_of[static_cast<std::size_t>(s.order[static_cast<std::size_t>(j)])] = j;
    const auto [begin, end] = thread_share(n);
    std::size_t pair_at = begin < std::min(end, pair_rows) ? first_of_body(s.row_a[static_cast<std::size_t>(begin)]) : 0;
    const int first_wall = std::max(begin, pair_rows);
    std::size_t body_at = first_wall < end ? first_of_body(s.row_a[static_cast<std::size_t>(first_wall)]) : 0;
    for (int g = begin; g < end; ++g) {
      const ContactKey key = key_of(g);
      std::size_t i;
      if (!is_wall(key.b)) {
        while (pair_at < nk && std::tie(kept[pair_at].key.a, kept[pair_at].key.b) < std::tie(key.a, key.b)) ++pair_at;
        i = pair_at;
      } else {
        while (body_at < nk && kept[body_at].key.a < key.a) ++body_at;
        i = body_at;
      }
      for (; i < nk && kept[i].key.a == key.a && (kept[i].key < key || kept[i].key == key); ++i)
        if (kept[i].key == key) {
          s.kept_impulse[static_cast<std::size_t>(g)] = static_cast<int>(i);
          break;
        }
    }
  }
}

}  // namespace ratchet
