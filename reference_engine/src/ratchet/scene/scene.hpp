// The scene definition: everything a run needs, read-only during the run
// (the "model" of the model/state/scratch split, docs/architecture.md).
// Symbols follow the paper: h time step, mu friction, p_gap gap relaxation,
// alpha_p / alpha_c thermal expansion of particles / container, theta_c opening angle.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/geometry/convex_polyhedron.hpp"

namespace ratchet {

struct Effects {
  bool gravity = true;
  bool friction = true;
  bool rotation = true;
  bool particle_expansion = true;
  bool container_expansion = true;
};

// What a Gauss-Seidel sweep's change is measured against (docs/method.md s. 7).
enum class Criterion {
  Impulse,   // ||d lambda|| / ||lambda||: the relative change of the contact impulses
  Velocity,  // the change of the body velocities in the kinetic-energy norm, relative to
             // the velocity the contact impulses give (blind to redundant impulses)
};

// The global contact solve (solver.method; World::solve's one switch). A new method is a
// file in solver/ with solve_nsgs's signature, an entry here and a case there.
enum class SolverMethod {
  Nsgs,  // non-linear Gauss-Seidel with the exact local Coulomb solve (solver/nsgs.hpp)
};

// How the Gauss-Seidel fixed point is reached (docs/method.md s. 7).
enum class Acceleration {
  None,      // plain sweeps
  Anderson,  // Anderson acceleration of the sweeps (solver/anderson.hpp)
};

// What a rigid solve does when its plain sweeps stall too (solver.stall_fallback,
// docs/method.md s. 7).
enum class StallFallback {
  Plain,  // go on sweeping to max_iterations
  Apgd,   // go on by the accelerated projected gradient (solver/apgd.hpp)
};

// The tangential part of the compliant law (solver.tangential_law, docs/method.md s. 5).
enum class TangentialLaw {
  Creep,   // u_t + c lambda_t: a sticking contact slides at c lambda_t while loaded
  Spring,  // u_t + c (lambda_t - lambda_t kept): it moves by c h per change of impulse, elastic
};

struct SolverSettings {
  SolverMethod method = SolverMethod::Nsgs;
  double tolerance = 1e-4;  // on the criterion's relative change between sweeps (docs/method.md s. 7)
  Criterion criterion = Criterion::Impulse;
  int max_iterations = 1000;
  Acceleration acceleration = Acceleration::Anderson;  // with the rigid law: bounded, and a second jam test (docs/method.md s. 7)
  int anderson_depth = 5;   // memory of the Anderson acceleration, in sweeps
  double theta = 1.0;       // Moreau-Jean theta in [0.5, 1]; 1 = fully implicit
  double p_gap = 0.1;       // fraction of an overlap closed per step, in (0, 1]
  double compliance = 0.0;  // epsilon >= 0: contact compliance c = epsilon W_nn; 0 = rigid (docs/method.md s. 5)
  // What a compliant sticking contact does under a steady tangential load: creep at c lambda_t
  // (the law on u + c lambda) or hold it as a spring (on u + c (lambda - lambda_kept)).
  TangentialLaw tangential_law = TangentialLaw::Creep;
  StallFallback stall_fallback = StallFallback::Plain;  // the rigid law only
  int slide_newton_steps = 0;  // > 0: a hinted slide's Newton budget (the inexact slide); 0: exact
  bool warm_start = true;
  double contact_margin = 0.05;  // contacts closer than this (length units) are detected
  double manifold_reuse = 0.0;   // a polyhedron pair's manifold is kept while it moves less (length; 0: rebuilt every step; contact/manifold_reuse.hpp)
  int threads = 0;          // 0: OpenMP default; results do not depend on it
};

struct Materials {
  double friction = 0.5;       // mu particle-particle
  double wall_friction = 0.5;  // mu particle-wall
  double density = 1.0;
};

struct ThermalProtocol {
  bool enabled = false;  // a scene without "thermal" has no thermal phase
  double T0 = 0.0, T1 = 100.0;
  double start_time = 0.0;  // T stays T0 until then (lets a bed settle first)
  double heat_time = 0.0, hold_time = 0.0, cool_time = 0.0;
  int cycles = 0;
  double alpha_p = 1e-4, alpha_c = 1e-3;
  double cycle_time() const { return heat_time + hold_time + cool_time + hold_time; }
};

enum class WallRole { Bottom, Side, Plane };

// A wall is a half-space {x : normal . (x - point) >= 0} holding the bodies on the
// side the normal points to. Container walls move with the container scale s_c.
struct WallDef {
  Vec3 normal = Vec3::UnitZ();
  Vec3 point = Vec3::Zero();  // at container scale 1
  WallRole role = WallRole::Plane;
  bool expands = false;       // moves with the container scale about scale_center
};

struct ContainerDef {
  enum class Type { None, Cone, Planes } type = Type::None;
  double bottom_radius = 8.5;     // to the middle of each flat segment
  double opening_angle_deg = 0.0; // angle of the side wall from the vertical
  int segments = 16;
  double height = 30.0;
  bool floor_expands = true;      // the floor's points move with the container scale (drag)
  Vec3 scale_center = Vec3::Zero();  // the bottom centre: container points scale about it
  std::vector<WallDef> walls;
};

// A body's kind of shape. Count is the number of kinds: it sizes the collision table
// (contact/collide.cpp) and the table of the kinds' facts (scene/shape_kinds.cpp).
enum class ShapeKind { Sphere, Polyhedron, Count };

struct BodyDef {
  ShapeKind kind = ShapeKind::Sphere;
  double radius = 0.0;       // sphere radius at scale 1
  int shape = -1;            // index into SceneDef::shapes for polyhedra
  Vec3 position = Vec3::Zero();  // centre of mass
  Quat orientation = Quat::Identity();  // body (principal) frame -> world
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
  bool fixed = false;
  double mass = 0.0;              // constant under expansion
  Vec3 principal_inertia = Vec3::Zero();  // at scale 1
  double bounding_radius = 0.0;   // at scale 1
};

// The thermal scale of a body when the particles' is s_p: fixed bodies do not expand.
inline double body_scale(const BodyDef& b, double s_p) { return b.fixed ? 1.0 : s_p; }

// What a run records beyond the always-present timeseries (docs/method.md s. 10). Each
// observable is computed only when asked for.
// A checkpoint of a run of the paper's bed every 2000 steps: about a minute and a half of
// its CPU (docs/performance.md), for a few milliseconds of writing.
constexpr int kDefaultCheckpointEvery = 2000;

struct OutputSettings {
  int timeseries_every = 1;  // steps between rows of timeseries.csv
  int bodies_every = 0;      // steps between snapshots in bodies.csv; 0: first and last only
  bool volume = false;       // V/V0 column: convex hull of all particle vertices (Qhull)
  bool segment_forces = false;  // wall_force_seg_<k> columns, one per side segment
  bool cycles = true;        // cycles.csv: one row per thermal cycle (thermal scenes only)
  int steady_first = -1, steady_last = -1;  // cycles averaged into P_max; -1: second half
  double displacement_cell = 0.0;           // > 0: displacement and vorticity fields
  std::vector<std::pair<int, int>> displacement_windows;  // cycle windows [a, b]
  bool displacement_stages = false;  // stage_fields.csv: fields over each heating and each cooling
  int wall_profile_bins = 0;  // > 0: wall_profile.csv, averaged over the cold hold of every cycle
  double settled_profile_time = 0.0;  // > 0: also the settled bed's profile, over this time before cycling
  double pressure_window = 0.5;  // time units: block average of P(t) for the per-cycle peaks
  std::vector<int> vtk_cycles;  // VTK at the ends of heating and cooling of these cycles (thermal cycles only)
  int vtk_every = 0;            // > 0: VTK of the first state, every step k with k % vtk_every == 0, and the last
  bool vtk_ascii = false;       // outputs.vtk_format "ascii": data arrays as text; "binary" (default): zlib-compressed
  int checkpoint_every = kDefaultCheckpointEvery;  // > 0: DIR/checkpoint.state every this many steps (run/checkpoint.hpp); 0: none
};

// The settle section (docs/scene-format.md, "settle"): the bed settles until its
// kinetic energy is at most ke_ratio x its peak, checked after every step, and fails
// the run if that has not happened by max_time. The thermal protocol and the duration
// then count from the end of the settle stage: thermal.start_time is the rest after
// it, time.duration the run after it. Until then SceneDef holds the latest possible
// values (settle end = max_time); World::end_settle_stage() puts in the real ones.
struct SettleDef {
  bool enabled = false;
  double ke_ratio = 0.0;
  double max_time = 0.0;
  double rest_time = 0.0;  // thermal.start_time as written
  double run_time = 0.0;   // time.duration as written, or rest_time + cycles x cycle time
};

struct SceneDef {
  std::string source;        // file the scene came from (for messages)
  int redrawn_particles = 0; // slivers the generator drew again (geometry/particle_generator.hpp)
  std::string name;
  std::uint64_t seed = 1;
  Vec3 gravity = Vec3(0.0, 0.0, -1.0);
  double dt = 1e-3;
  double duration = 0.0;
  std::int64_t steps = 0;    // round(duration / dt)
  SolverSettings solver;
  Materials materials;
  Effects effects;
  ContainerDef container;
  ThermalProtocol thermal;
  OutputSettings outputs;
  SettleDef settle;
  std::vector<ConvexPolyhedron> shapes;
  std::vector<BodyDef> bodies;
  nlohmann::json as_run;     // the scene JSON as run: the file after --set overrides
  std::string hash;          // FNV-1a 64 of as_run.dump(), hex
  // as_run with every default filled in: each field the reader took a default for, with
  // that default (and time.duration when derived from the thermal protocol). Sections
  // whose absence means "none" (container, thermal, settle, outputs.displacement,
  // particles.generate.region) stay absent. Read back, it gives the same scene.
  nlohmann::json effective;
};

// Thrown for any malformed scene: the message names the file, the field and what was
// expected. Nothing has been written when it is thrown.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Applies "key.path=value" overrides (value parsed as JSON, else taken as a string).
void apply_override(nlohmann::json& scene, const std::string& assignment, const std::string& source);

// Reads, checks and builds a scene. Generated particles are created here from the seed.
SceneDef load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
SceneDef build_scene(const nlohmann::json& scene, const std::string& source);

// Stable 64-bit FNV-1a hash as 16 hex digits.
std::string fnv1a_hex(const std::string& bytes);

}  // namespace ratchet
