// VTK snapshots of a run for ParaView (docs/output-format.md, "VTK files"): at the ends
// of heating and cooling of the cycles in outputs.vtk_cycles, and with
// outputs.vtk_every = N at the run's first state, after every step k with k % N == 0
// and after the last step. A snapshot is written under DIR/vtk/ as particles_<tag>.vtp,
// contacts_<tag>.vtp, force_chains_<tag>.vtp and (with a container) container_<tag>.vtp
// (observe/vtk_writer.hpp, observe/container_mesh.hpp); after each, the indexes
// particles.pvd, contacts.pvd, force_chains.pvd and container.pvd are rewritten (observe/pvd_writer.hpp),
// so a killed run still leaves a valid index of what it wrote. Only reads the world.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/observe/container_mesh.hpp"
#include "ratchet/observe/pvd_writer.hpp"
#include "ratchet/observe/vtk_writer.hpp"
#include "ratchet/run/accumulator.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

// Everything one snapshot writes, taken from a world.
struct VtkSnapshot {
  VtkTime time;
  std::vector<VtkBody> bodies;
  std::vector<VtkContact> contacts;  // every contact point of the last step, open ones too
  ContainerMesh container;
  std::vector<Vec3> wall_normal;   // per container polygon
  std::vector<double> wall_force;  // per container polygon: sum of lambda_n / h over its wall's contacts
};

// The world's current state and last step's contacts as a snapshot.
VtkSnapshot take_vtk_snapshot(const World& world);

// The tag of the snapshot of step k under outputs.vtk_every: "step" and k with at least
// 8 digits (step00001200).
std::string vtk_step_tag(std::int64_t step);

class VtkSnapshots final : public Accumulator {
 public:
  // At the run's first state; out_dir empty: no files. A resumed run (run/checkpoint.hpp)
  // passes first_state = false: its first state was written before the interruption.
  VtkSnapshots(const World& world, std::string out_dir, bool first_state = true);

  // After every step. (An earlier run's VTK files were removed by the runner before this
  // object wrote the first state: remove_previous_outputs, run/run_output.hpp.)
  void after_step(const World& world, const ClockTick& tick) override;

  // Writes the current state under `tag` and indexes it.
  void write(const World& world, const std::string& tag);

  // A checkpoint's record (the indexes so far), and its restore, which rewrites the
  // .pvd indexes as they were at the checkpoint: snapshots an interrupted run wrote
  // after it are dropped from them until the resumed run writes them again.
  nlohmann::json save() const override;
  void restore(const nlohmann::json& j) override;

 private:
  void write(const VtkSnapshot& snap, const std::string& tag);

  const SceneDef& scene_;
  std::string out_dir_;
  std::int64_t last_indexed_step_ = -1;
  std::vector<PvdEntry> particles_, contacts_, container_, force_chains_;
};

}  // namespace ratchet
