// Phase 3 of the step, contact detection: bodies placed at the current pose and scale,
// candidate pairs from the grid, the narrow phase through the collision table
// (contact/collide.hpp), gathered into the step's contact list in a fixed order.
#include <algorithm>

#include <cmath>

#include "ratchet/contact/collide.hpp"
#include "ratchet/world/test_hooks.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

namespace {

// Below this many bodies or pairs a parallel region costs more than it saves.
constexpr int kParallelMin = 256;
// The skin of the kept pair list, in units of the largest bounding radius: a cycled bed
// moves about 1e-4 of it per step, so the grid is searched every few hundred steps.
constexpr double kPairSkin = 0.1;

}  // namespace

void World::prepare_bodies() {
  const std::size_t n = scene_.bodies.size();
  StepScratch& s = scratch_;
  s.R.resize(n);
  s.inv_inertia.resize(n);
  s.inv_mass.resize(n);
  s.scale.resize(n);
  s.vertex_offset.resize(n);
  s.centers.resize(n);
  s.radii.resize(n);
  s.placed.resize(n);
  int total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const int count = placed_vertex_count(scene_, scene_.bodies[i]);
    s.vertex_offset[i] = count > 0 ? total : -1;
    total += count;
  }
  s.world_vertices.resize(static_cast<std::size_t>(total));
#pragma omp parallel for schedule(static) if (n > static_cast<std::size_t>(kParallelMin))
  for (std::size_t i = 0; i < n; ++i) {
    const BodyDef& b = scene_.bodies[i];
    const double sc = body_scale(static_cast<int>(i));
    s.scale[i] = sc;
    s.R[i] = state_.q[i].toRotationMatrix();
    s.inv_mass[i] = b.fixed ? 0.0 : 1.0 / b.mass;
    if (b.fixed || !rotation_on_) {
      s.inv_inertia[i].setZero();
    } else {
      // Inertia scales with s^2 at constant mass.
      const Vec3 inv_I = (b.principal_inertia * (sc * sc)).cwiseInverse();
      s.inv_inertia[i] = s.R[i] * inv_I.asDiagonal() * s.R[i].transpose();
    }
    s.centers[i] = state_.x[i];
    s.radii[i] = b.bounding_radius * sc;
    const int offset = s.vertex_offset[i];
    Vec3* vertices = offset >= 0 ? &s.world_vertices[static_cast<std::size_t>(offset)] : nullptr;
    s.placed[i] = place_collision_body(scene_, b, state_.x[i], s.R[i], sc, vertices);
  }
}

// Common planes of the last step, looked up by pair (both lists are sorted); each slot
// written once, the kept plane or none.
void World::load_pair_planes() {
  StepScratch& s = scratch_;
  s.pair_planes.resize(s.pairs.size());
  std::size_t j = 0;
  for (std::size_t k = 0; k < s.pairs.size(); ++k) {
    while (j < state_.planes.size() && std::make_pair(state_.planes[j].a, state_.planes[j].b) < s.pairs[k]) ++j;
    const bool kept = j < state_.planes.size() && std::make_pair(state_.planes[j].a, state_.planes[j].b) == s.pairs[k];
    s.pair_planes[k] = kept ? state_.planes[j].cache : CommonPlaneCache{};
  }
}

// Keep the planes of the polyhedron pairs for the next step.
void World::store_pair_planes() {
  const StepScratch& s = scratch_;
  state_.planes.clear();
  for (std::size_t k = 0; k < s.pairs.size(); ++k)
    if (s.pair_planes[k].valid) state_.planes.push_back({s.pairs[k].first, s.pairs[k].second, s.pair_planes[k]});
}

// Kept manifolds of the last step, looked up by pair (both lists are sorted).
void World::load_pair_manifolds() {
  StepScratch& s = scratch_;
  s.pair_kept.assign(s.pairs.size(), -1);
  s.pair_keep.resize(s.pairs.size());
  s.pair_replayed.assign(s.pairs.size(), 0);
  std::size_t j = 0;
  const std::vector<KeptManifold>& kept = state_.manifolds;
  for (std::size_t k = 0; k < s.pairs.size(); ++k) {
    s.pair_keep[k].count = -1;
    while (j < kept.size() && std::make_pair(kept[j].a, kept[j].b) < s.pairs[k]) ++j;
    if (j < kept.size() && std::make_pair(kept[j].a, kept[j].b) == s.pairs[k]) s.pair_kept[k] = static_cast<int>(j);
  }
}

void World::reduce_reuse_audit() {
  ReuseAudit& audit = *test_hooks().reuse_audit;
  for (const PairAudit& p : scratch_.pair_audit) {
    if (!p.compared) continue;
    ++audit.replayed;
    audit.empty_violations += p.empty_violation ? 1 : 0;
    audit.max_gap_error = std::max(audit.max_gap_error, p.error);
    audit.max_error_per_motion = std::max(audit.max_error_per_motion, p.per_motion);
  }
}

// Keep the manifolds of this step's polyhedron pairs (replayed ones with the pose they
// were built at) for the next step.
void World::store_pair_manifolds() {
  StepScratch& s = scratch_;
  std::vector<KeptManifold> next;
  next.reserve(s.pairs.size());
  int replayed = 0, built = 0;
  for (std::size_t k = 0; k < s.pairs.size(); ++k) {
    if (s.pair_replayed[k]) {  // kept as it was (not copied to pair_keep first)
      next.push_back(state_.manifolds[static_cast<std::size_t>(s.pair_kept[k])]);
      ++replayed;
    } else if (s.pair_keep[k].count >= 0) {
      next.push_back(s.pair_keep[k]);
      ++built;
    }
  }
  state_.manifolds.swap(next);
  stats_.manifolds_replayed = replayed;
  stats_.manifolds_built = built;
}

// A polyhedron pair under solver.manifold_reuse (contact/manifold_reuse.hpp): its kept
// manifold replayed while the pair has moved less than the bound since the build (an
// empty one only while the gap's lower bound stays beyond the margin), else built anew
// and kept.
void World::collide_reusing(int k, const CollisionBody& a, const CollisionBody& b) {
  StepScratch& s = scratch_;
  const std::size_t slot = static_cast<std::size_t>(k);
  const double bound = scene_.solver.manifold_reuse, margin = scene_.solver.contact_margin;
  ContactManifold& m = s.pair_manifolds[slot];
  if (s.pair_kept[slot] >= 0) {
    const KeptManifold& kept = state_.manifolds[static_cast<std::size_t>(s.pair_kept[slot])];
    const double moved = pair_motion(kept.pose, pair_pose(a.poly, b.poly), a.poly.shape->bounding_radius,
                                     b.poly.shape->bounding_radius);
    if (moved <= bound && (kept.count > 0 || kept.gap_bound - moved > margin)) {
      replay_manifold(kept, a.poly, b.poly, m);
      s.pair_replayed[slot] = 1;  // store_pair_manifolds keeps it from the state
      if (s.audit_on) audit_replay(slot, a, b, moved);
      return;
    }
  }
  CommonPlaneResult plane;
  collide_polyhedra(a.poly, b.poly, margin, s.pair_planes[slot], m, &plane);
  s.pair_keep[slot] = keep_manifold(s.pairs[slot].first, s.pairs[slot].second, a.poly, b.poly, m, plane.gap,
                                    plane.feature == PlaneFeature::FaceB);
}

// Test hook (world/test_hooks.hpp): the replayed manifold of pair `slot` against a fresh
// build at the same poses, into the pair's audit slot.
void World::audit_replay(std::size_t slot, const CollisionBody& a, const CollisionBody& b, double moved) {
  StepScratch& s = scratch_;
  const ContactManifold& m = s.pair_manifolds[slot];
  CommonPlaneCache cache = s.pair_planes[slot];  // a copy: the audit changes nothing
  ContactManifold fresh;
  collide_polyhedra(a.poly, b.poly, scene_.solver.contact_margin, cache, fresh);
  PairAudit& out = s.pair_audit[slot];
  out.compared = true;
  if (m.count == 0) {
    out.empty_violation = fresh.count > 0;
    return;
  }
  double deepest_replayed = HUGE_VAL, deepest_fresh = HUGE_VAL;
  for (int c = 0; c < m.count; ++c) deepest_replayed = std::min(deepest_replayed, m.points[static_cast<std::size_t>(c)].gap);
  for (int c = 0; c < fresh.count; ++c) deepest_fresh = std::min(deepest_fresh, fresh.points[static_cast<std::size_t>(c)].gap);
  // A fresh build found nothing within the margin: the exact gap is beyond it.
  if (fresh.count == 0) deepest_fresh = scene_.solver.contact_margin;
  out.error = std::abs(deepest_replayed - deepest_fresh);
  out.per_motion = moved > 0.0 ? out.error / moved : (out.error > 0.0 ? HUGE_VAL : 0.0);
}

// (body, wall) candidates whose bounding sphere reaches within the margin of the wall
// plane, body-major.
void World::find_wall_pairs(const std::vector<Vec3>& wall_points) {
  StepScratch& s = scratch_;
  const double margin = scene_.solver.contact_margin;
  const int n = static_cast<int>(scene_.bodies.size());
  const int nw = static_cast<int>(scene_.container.walls.size());
  s.wall_pairs.clear();
  for (int i = 0; i < n; ++i) {
    if (scene_.bodies[static_cast<std::size_t>(i)].fixed) continue;
    for (int w = 0; w < nw; ++w) {
      const WallDef& wall = scene_.container.walls[static_cast<std::size_t>(w)];
      if (wall.normal.dot(s.centers[static_cast<std::size_t>(i)] - wall_points[static_cast<std::size_t>(w)]) -
              s.radii[static_cast<std::size_t>(i)] <= margin)
        s.wall_pairs.emplace_back(i, w);
    }
  }
}

// Gather in a fixed order: body pairs (sorted), then bodies against walls; then into
// the colour order of the parallel sweep (solver/row_colouring.hpp), a function of this
// list alone, so the same for any thread count.
void World::gather_contacts() {
  StepScratch& s = scratch_;
  s.gathered.clear();
  for (std::size_t k = 0; k < s.pairs.size(); ++k) {
    const ContactManifold& m = s.pair_manifolds[k];
    for (int c = 0; c < m.count; ++c) {
      SolverContact sc;
      sc.a = s.pairs[k].first;
      sc.b = s.pairs[k].second;
      sc.geometry = m.points[static_cast<std::size_t>(c)];
      sc.mu = scene_.materials.friction;
      s.gathered.push_back(sc);
    }
  }
  for (std::size_t k = 0; k < s.wall_pairs.size(); ++k) {
    const ContactManifold& m = s.wall_manifolds[k];
    for (int c = 0; c < m.count; ++c) {
      SolverContact sc;
      sc.a = s.wall_pairs[k].first;
      sc.b = wall_side(s.wall_pairs[k].second);
      sc.geometry = m.points[static_cast<std::size_t>(c)];
      sc.mu = scene_.materials.wall_friction;
      s.gathered.push_back(sc);
    }
  }
  const std::size_t n = s.gathered.size();
  s.row_a.resize(n);
  s.row_b.resize(n);
  for (std::size_t k = 0; k < n; ++k) { s.row_a[k] = s.gathered[k].a; s.row_b[k] = s.gathered[k].b; }
  if (s.moving.size() != scene_.bodies.size()) {  // which bodies are fixed never changes
    s.moving.resize(scene_.bodies.size());
    for (std::size_t i = 0; i < scene_.bodies.size(); ++i) s.moving[i] = !scene_.bodies[i].fixed;
  }
  colour_rows(s.row_a, s.row_b, s.moving, s.order, s.colouring);
  s.contacts.resize(n);
  for (std::size_t j = 0; j < n; ++j) s.contacts[j] = s.gathered[static_cast<std::size_t>(s.order[j])];
}

// 3. Contact detection: the narrow phase runs in parallel into per-pair slots, which
// are gathered in pair order, so the list is the same for any thread count.
void World::detect() {
  prepare_bodies();
  StepScratch& s = scratch_;
  const double margin = scene_.solver.contact_margin;
  if (s.pair_skin < 0.0) {
    double r_max = 0.0;
    for (const BodyDef& b : scene_.bodies) r_max = std::max(r_max, b.bounding_radius);
    s.pair_skin = kPairSkin * (r_max > 0.0 ? r_max : 1.0);
  }
  s.pair_list.find(s.centers, s.radii, margin, s.pair_skin, s.pairs);
  s.pair_manifolds.resize(s.pairs.size());  // every slot's count is set below
  const int np = static_cast<int>(s.pairs.size());
  load_pair_planes();
  const bool reuse = scene_.solver.manifold_reuse > 0.0;
  if (reuse) load_pair_manifolds();
  s.audit_on = reuse && test_hooks().reuse_audit != nullptr;
  if (s.audit_on) s.pair_audit.assign(s.pairs.size(), PairAudit{});
#pragma omp parallel for schedule(dynamic, 64) if (np > kParallelMin)
  for (int k = 0; k < np; ++k) {
    const int a = s.pairs[static_cast<std::size_t>(k)].first, b = s.pairs[static_cast<std::size_t>(k)].second;
    ContactManifold& m = s.pair_manifolds[static_cast<std::size_t>(k)];
    m.count = 0;
    if (scene_.bodies[static_cast<std::size_t>(a)].fixed && scene_.bodies[static_cast<std::size_t>(b)].fixed) continue;
    const CollisionBody& ca = s.placed[static_cast<std::size_t>(a)];
    const CollisionBody& cb = s.placed[static_cast<std::size_t>(b)];
    if (reuse && manifold_reusable(ca, cb)) collide_reusing(k, ca, cb);
    else collide_pair(ca, cb, margin, s.pair_planes[static_cast<std::size_t>(k)], m);
  }
  store_pair_planes();
  if (reuse) store_pair_manifolds();
  if (reuse && s.audit_on) reduce_reuse_audit();
  const int nw = static_cast<int>(scene_.container.walls.size());
  std::vector<Vec3> wall_points(static_cast<std::size_t>(nw));
  for (int w = 0; w < nw; ++w) wall_points[static_cast<std::size_t>(w)] = wall_point(w);
  find_wall_pairs(wall_points);
  const int nwp = static_cast<int>(s.wall_pairs.size());
  s.wall_manifolds.resize(s.wall_pairs.size());
#pragma omp parallel for schedule(dynamic, 64) if (nwp > kParallelMin)
  for (int k = 0; k < nwp; ++k) {
    const int i = s.wall_pairs[static_cast<std::size_t>(k)].first, w = s.wall_pairs[static_cast<std::size_t>(k)].second;
    collide_wall(s.placed[static_cast<std::size_t>(i)], scene_.container.walls[static_cast<std::size_t>(w)].normal,
                 wall_points[static_cast<std::size_t>(w)], margin, s.wall_manifolds[static_cast<std::size_t>(k)]);
  }
  gather_contacts();
}

}  // namespace ratchet
