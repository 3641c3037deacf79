// VTK files at the ends of heating and cooling of the cycles in outputs.vtk_cycles
// (docs/output-format.md, "VTK files"): particle shapes and the contact force network,
// written with observe/vtk_writer.hpp under DIR/vtk/.
#pragma once

#include <string>

#include "ratchet/run/cycle_clock.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

class VtkSnapshots {
 public:
  // No files when out_dir is empty.
  VtkSnapshots(const SceneDef& scene, std::string out_dir) : scene_(scene), out_dir_(std::move(out_dir)) {}
  void after_step(const World& world, const ClockTick& tick) const;
  // DIR/vtk/particles_<tag>.vtk and contacts_<tag>.vtk of the current state.
  void write(const World& world, const std::string& tag) const;

 private:
  const SceneDef& scene_;
  std::string out_dir_;
};

}  // namespace ratchet
