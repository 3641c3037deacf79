// Displacement fields over each heating and each cooling (paper Fig. 5; docs/output-format.md,
// `stage_fields.csv`; outputs.displacement.stages): the body centres kept at the start of
// the current cycle and at its end of heating; at its end of cooling both stage fields
// are computed on the grid of observe/displacement_field.hpp and kept as text rows, which
// are written at the end of the run. Scenes that do not ask for it keep nothing.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/run/accumulator.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

inline constexpr const char* kStageFieldsFileName = "stage_fields.csv";

class StageFields final : public Accumulator {
 public:
  // The start of cycle 0 is the first state when that already is the start of cycling.
  StageFields(const World& world, const CycleClock& clock);
  bool enabled() const { return scene_.outputs.displacement_stages && scene_.outputs.displacement_cell > 0.0; }
  void after_step(const World& world, const ClockTick& tick) override;
  // DIR/stage_fields.csv: the rows of every cycle whose cooling ended.
  void write(const std::string& out_dir) const;
  void finish(const RunEnd& end, nlohmann::json& summary) const override;  // write, thermal runs with files
  nlohmann::json save() const override;
  void restore(const nlohmann::json& j) override;

 private:
  void start_cycle(const std::vector<Vec3>& x, int cycle);
  void add_rows(int cycle, const std::vector<Vec3>& cooled);

  const SceneDef& scene_;
  int nr_ = 0, nz_ = 0;     // the grid, fixed at the start of cycling
  int start_cycle_ = -1;    // the cycle whose start `start_` holds
  int heated_cycle_ = -1;   // the cycle whose end of heating `heated_` holds
  std::vector<Vec3> start_, heated_;
  std::string rows_;        // CSV rows of the cycles done, without the header
};

}  // namespace ratchet
