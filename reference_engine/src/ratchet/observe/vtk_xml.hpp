// The body of a VTK XML PolyData file ("VTK User's Guide", "VTK File Formats", XML
// format) and how its data arrays are encoded (docs/output-format.md, "VTK files"):
// - Binary (the default): every point and cell array in one <AppendedData
//   encoding="raw"> block, each array compressed with zlib (compressor
//   "vtkZLibDataCompressor", header_type UInt64: [blocks, block size, last block size,
//   compressed sizes...] then the blocks). Values are the doubles and integers as they
//   are in memory (little endian), so they read back bit for bit.
// - Ascii: every array inline as text; doubles in their shortest round-trip form, so
//   they read back to the same bits as the binary file's.
// The field data (TimeValue, step) stay inline text in both: two numbers, readable with
// grep. Plain data: the caller builds the arrays, this only lays them out.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ratchet {

enum class VtkEncoding { Binary, Ascii };

// "binary" / "ascii", the names of outputs.vtk_format.
const char* vtk_encoding_name(VtkEncoding e);

// The state a file shows: field data TimeValue (double) and step (Int64).
struct VtkTime {
  double t = 0.0;
  std::int64_t step = 0;
};

class VtkXml {
 public:
  // Opens the file's text: header, field data and the <Piece> with these counts.
  VtkXml(VtkEncoding encoding, const VtkTime& time, std::size_t points, std::size_t verts, std::size_t lines,
         std::size_t polys);

  // A section (PointData, CellData, Points, Verts, Lines, Polys) around its arrays.
  void open(const char* section);
  void close(const char* section);

  // One array of `components` values per tuple (values.size() a multiple of it).
  void array(const char* name, int components, const std::vector<double>& values);    // Float64
  void array(const char* name, int components, const std::vector<std::int32_t>& values);  // Int32
  void array(const char* name, int components, const std::vector<std::int64_t>& values);  // Int64

  // The whole file; the object is spent.
  std::string finish();

 private:
  template <class T>
  void add(const char* type, const char* name, int components, const std::vector<T>& values);
  VtkEncoding encoding_;
  std::string text_;      // the XML so far
  std::string appended_;  // the compressed arrays, in order (Binary)
};

}  // namespace ratchet
