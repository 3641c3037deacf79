// ParaView data collections (.pvd; docs/output-format.md, "VTK files"): an XML index of
// data files, each with its time, so that ParaView opens a series of snapshots as one
// animation (File -> Open the .pvd). The files must be VTK XML files (.vtp and the
// like): ParaView's collection reader picks the reader by the XML extension and has
// none for legacy .vtk. Written atomically (io/atomic_file.hpp). Plain data.
#pragma once

#include <string>
#include <vector>

namespace ratchet {

struct PvdEntry {
  double time = 0.0;  // the simulated time the file shows (attribute timestep)
  std::string file;   // relative to the folder of the .pvd
};

// <VTKFile type="Collection"> with one <DataSet timestep=".." group="" part="0"
// file=".."/> per entry, in the given order; times with 17 significant digits (they
// read back to the same double). Throws std::invalid_argument for a non-finite time or
// an empty file name (nothing written), std::runtime_error on I/O failure.
void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries);

}  // namespace ratchet
