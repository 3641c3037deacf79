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

// The state's kept planes and manifolds, one per candidate pair of the broad phase and in
// its order (world/state.hpp), so that the narrow phase reads and updates them in place.
// The candidates change only at a new grid search (contact/pair_list.hpp); then, or when
// the state came from elsewhere (a packing, a checkpoint: compact lists), each kept entry
// moves to its pair's new slot and the other slots hold nothing.
namespace {

template <class Kept>
bool aligned(const std::vector<Kept>& kept, const std::vector<BodyPair>& candidates) {
  if (kept.size() != candidates.size()) return false;
  for (std::size_t k = 0; k < kept.size(); ++k)
    if (kept[k].a != candidates[k].first || kept[k].b != candidates[k].second) return false;
  return true;
}

// holds(entry): whether an old entry carries something to keep.
template <class Kept, class Holds>
void realign(std::vector<Kept>& kept, const std::vector<BodyPair>& candidates, const Kept& none, Holds holds) {
  std::vector<Kept> next(candidates.size(), none);
  std::size_t j = 0;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    next[k].a = candidates[k].first;
    next[k].b = candidates[k].second;
    while (j < kept.size() && std::make_pair(kept[j].a, kept[j].b) < candidates[k]) ++j;
    if (j < kept.size() && std::make_pair(kept[j].a, kept[j].b) == candidates[k] && holds(kept[j])) next[k] = kept[j];
  }
  kept.swap(next);
}

}  // namespace

void World::align_pair_slots(const std::vector<BodyPair>& candidates, bool reuse) {
  StepScratch& s = scratch_;
  // Aligned at the last step, with the same candidates and the state not handed out for
  // change since (mutable_state): nothing to check (the check reads every slot's pair).
  if (s.slots_aligned && s.slots_search == s.pair_list.searches()) return;
  s.slots_aligned = true;
  s.slots_search = s.pair_list.searches();
  if (!aligned(state_.planes, candidates))
    realign(state_.planes, candidates, KeptPlane{}, [](const KeptPlane& p) { return p.cache.valid; });
  if (reuse && !aligned(state_.manifolds, candidates)) {
    KeptManifold none;
    none.count = -1;
    realign(state_.manifolds, candidates, none, [](const KeptManifold& m) { return m.count >= 0; });
  }
}

// The replayed and the built manifolds of this step (StepStats).
void World::count_pair_fates() {
  int replayed = 0, built = 0;
  for (const char f : scratch_.pair_fate) {
    replayed += f == kReplayed ? 1 : 0;
    built += f == kBuilt ? 1 : 0;
  }
  stats_.manifolds_replayed = replayed;
  stats_.manifolds_built = built;
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

// A polyhedron pair under solver.manifold_reuse (contact/manifold_reuse.hpp): its kept
// manifold replayed while the pair has moved less than the bound since the build (an
// empty one only while the gap's lower bound stays beyond the margin), else built anew
// and kept.
void World::collide_reusing(int k, const CollisionBody& a, const CollisionBody& b) {
  StepScratch& s = scratch_;
  const std::size_t slot = static_cast<std::size_t>(k);
  const double bound = scene_.solver.manifold_reuse, margin = scene_.solver.contact_margin;
  ContactManifold& m = s.pair_manifolds[slot];
  KeptManifold& kept = state_.manifolds[slot];
  if (kept.count >= 0) {
    const double moved = pair_motion(kept.pose, pair_pose(a.poly, b.poly), a.poly.shape->bounding_radius,
                                     b.poly.shape->bounding_radius);
    if (moved <= bound && (kept.count > 0 || kept.gap_bound - moved > margin)) {
      replay_manifold(kept, a.poly, b.poly, m);
      s.pair_fate[slot] = kReplayed;  // kept as it was
      if (s.audit_on) audit_replay(slot, a, b, moved);
      return;
    }
  }
  CommonPlaneResult plane;
  collide_polyhedra(a.poly, b.poly, margin, state_.planes[slot].cache, m, &plane);
  kept = keep_manifold(kept.a, kept.b, a.poly, b.poly, m, plane.gap, plane.feature == PlaneFeature::FaceB);
  s.pair_fate[slot] = kBuilt;
}

// Test hook (world/test_hooks.hpp): the replayed manifold of pair `slot` against a fresh
// build at the same poses, into the pair's audit slot.
void World::audit_replay(std::size_t slot, const CollisionBody& a, const CollisionBody& b, double moved) {
  StepScratch& s = scratch_;
  const ContactManifold& m = s.pair_manifolds[slot];
  CommonPlaneCache cache = state_.planes[slot].cache;  // a copy: the audit changes nothing
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

// Gather in a fixed order: body pairs (the candidates, sorted), then bodies against
// walls; then into the colour order of the parallel sweep (solver/row_colouring.hpp), a
// function of this list alone, so the same for any thread count. Each contact is made
// once, at its place in the colour order, from its manifold point (gathered_from).
void World::gather_contacts() {
  StepScratch& s = scratch_;
  const std::vector<BodyPair>& pairs = *s.candidates;
  s.row_a.clear();
  s.row_b.clear();
  s.gathered_from.clear();
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const int count = s.pair_manifolds[k].count;  // 0 for a candidate out of reach
    for (int c = 0; c < count; ++c) {
      s.row_a.push_back(pairs[k].first);
      s.row_b.push_back(pairs[k].second);
      s.gathered_from.push_back({static_cast<int>(k), c});
    }
  }
  for (std::size_t k = 0; k < s.wall_pairs.size(); ++k) {
    const int count = s.wall_manifolds[k].count;
    for (int c = 0; c < count; ++c) {
      s.row_a.push_back(s.wall_pairs[k].first);
      s.row_b.push_back(wall_side(s.wall_pairs[k].second));
      s.gathered_from.push_back({-1 - static_cast<int>(k), c});
    }
  }
  if (s.moving.size() != scene_.bodies.size()) {  // which bodies are fixed never changes
    s.moving.resize(scene_.bodies.size());
    for (std::size_t i = 0; i < scene_.bodies.size(); ++i) s.moving[i] = !scene_.bodies[i].fixed;
  }
  colour_rows(s.row_a, s.row_b, s.moving, s.order, s.colouring);
  const int n = static_cast<int>(s.row_a.size());
  s.contacts.resize(static_cast<std::size_t>(n));
  const int parallel_min = parallel_min_rows();
  // Each contact from its own manifold point: any split among threads gives the same list.
#pragma omp parallel for schedule(static) if (n > parallel_min)
  for (int j = 0; j < n; ++j) {
    const std::size_t g = static_cast<std::size_t>(s.order[static_cast<std::size_t>(j)]);
    const GatheredFrom from = s.gathered_from[g];
    const bool wall = from.manifold < 0;
    const ContactManifold& m = wall ? s.wall_manifolds[static_cast<std::size_t>(-1 - from.manifold)]
                                    : s.pair_manifolds[static_cast<std::size_t>(from.manifold)];
    SolverContact sc;
    sc.a = s.row_a[g];
    sc.b = s.row_b[g];
    sc.geometry = m.points[static_cast<std::size_t>(from.point)];
    sc.mu = wall ? scene_.materials.wall_friction : scene_.materials.friction;
    s.contacts[static_cast<std::size_t>(j)] = sc;
  }
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
  const std::vector<BodyPair>& pairs = s.pair_list.mark(s.centers, s.radii, margin, s.pair_skin, s.in_reach);
  s.candidates = &pairs;
  const int np = static_cast<int>(pairs.size());
  s.pair_manifolds.resize(pairs.size());  // every slot's count is set below
  const bool reuse = scene_.solver.manifold_reuse > 0.0;
  align_pair_slots(pairs, reuse);
  s.pair_fate.assign(pairs.size(), kNotKept);
  s.audit_on = reuse && test_hooks().reuse_audit != nullptr;
  if (s.audit_on) s.pair_audit.assign(pairs.size(), PairAudit{});
#pragma omp parallel for schedule(dynamic, 64) if (np > kParallelMin)
  for (int k = 0; k < np; ++k) {
    const std::size_t slot = static_cast<std::size_t>(k);
    const int a = pairs[slot].first, b = pairs[slot].second;
    ContactManifold& m = s.pair_manifolds[slot];
    CommonPlaneCache& plane = state_.planes[slot].cache;
    m.count = 0;
    if (!s.in_reach[slot]) {  // as if not a pair: nothing kept
      if (plane.valid) plane = CommonPlaneCache{};
      if (reuse) state_.manifolds[slot].count = -1;
      continue;
    }
    if (scene_.bodies[static_cast<std::size_t>(a)].fixed && scene_.bodies[static_cast<std::size_t>(b)].fixed) {
      if (reuse) state_.manifolds[slot].count = -1;
      continue;
    }
    const CollisionBody& ca = s.placed[static_cast<std::size_t>(a)];
    const CollisionBody& cb = s.placed[static_cast<std::size_t>(b)];
    if (reuse && manifold_reusable(ca, cb)) {
      collide_reusing(k, ca, cb);
    } else {
      collide_pair(ca, cb, margin, plane, m);
      if (reuse) state_.manifolds[slot].count = -1;
    }
    if (!plane.valid) plane = CommonPlaneCache{};  // an invalid plane keeps nothing
  }
  if (reuse) count_pair_fates();
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
