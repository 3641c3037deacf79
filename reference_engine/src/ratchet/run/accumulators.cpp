#include "ratchet/run/accumulators.hpp"

#include <iterator>

#include "ratchet/run/cycle_stats.hpp"
#include "ratchet/run/displacement_windows.hpp"
#include "ratchet/run/pressure_peaks.hpp"
#include "ratchet/run/segment_forces.hpp"
#include "ratchet/run/stage_fields.hpp"
#include "ratchet/run/volume_ratio.hpp"
#include "ratchet/run/vtk_snapshots.hpp"
#include "ratchet/run/wall_profile.hpp"

namespace ratchet {

namespace {

template <class A, class... Args>
std::unique_ptr<Accumulator> own(Args&&... args) {
  return std::make_unique<A>(std::forward<Args>(args)...);
}

std::vector<AccumulatorEntry>& entries() {
  using S = const ObserverSetup&;
  // The checkpoint keys are those of the first checkpoints: changing one breaks resuming.
  static std::vector<AccumulatorEntry> list = {
      {"peaks", [](S s) { return own<PressurePeaks>(s.world.scene()); }},
      {"volume", [](S s) { return own<VolumeRatio>(s.world); }},
      {"cycle_stats", [](S) { return own<CycleStats>(); }},
      {nullptr, [](S s) { return own<SegmentForces>(s.world.scene()); }},
      {"wall_profile", [](S s) { return own<WallProfile>(s.world.scene()); }},
      {"displacement", [](S s) { return own<DisplacementWindows>(s.world, s.clock); }},
      {"stage_fields", [](S s) { return own<StageFields>(s.world, s.clock); }},
      {"vtk", [](S s) { return own<VtkSnapshots>(s.world, s.out_dir, !s.resuming); }},
  };
  return list;
}

}  // namespace

const std::vector<AccumulatorEntry>& accumulator_entries() { return entries(); }

ScopedAccumulator::ScopedAccumulator(const AccumulatorEntry& entry) : entry_(entry) { entries().push_back(entry); }

// The last equal entry: guards taken out of order still leave the others' entries.
ScopedAccumulator::~ScopedAccumulator() {
  std::vector<AccumulatorEntry>& list = entries();
  for (auto it = list.rbegin(); it != list.rend(); ++it)
    if (it->key == entry_.key && it->make == entry_.make) {
      list.erase(std::next(it).base());
      return;
    }
}

}  // namespace ratchet
