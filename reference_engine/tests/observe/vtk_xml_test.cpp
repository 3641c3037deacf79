// The layout of VTK XML files (observe/vtk_xml.hpp): the compressed blocks of an
// appended array (VTK's UInt64 header, blocks of 32768 bytes, a partial last one), an
// empty array, ASCII text that reads back to the same doubles, and arrays that are not
// whole tuples refused. vtk_writer_test.cpp checks whole files in both encodings.
#include "ratchet/observe/vtk_xml.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ratchet {
namespace {

std::uint64_t u64(const std::string& s, std::size_t at) {
  std::uint64_t x = 0;
  std::memcpy(&x, s.data() + at, 8);
  return x;
}

// The raw bytes after the "_" of <AppendedData>.
std::string raw_data(const std::string& file) {
  const std::string tag = "<AppendedData encoding=\"raw\">\n_";
  const std::size_t at = file.find(tag);
  EXPECT_NE(at, std::string::npos);
  return file.substr(at + tag.size());
}

TEST(VtkXml, AppendedArraysAreZlibBlocksOf32KiBWithVtksHeader) {
  std::vector<double> big(10000);  // 80000 bytes: two whole blocks and a partial one
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = 0.5 * static_cast<double>(i) + 1.0 / 3.0;
  VtkXml xml(VtkEncoding::Binary, {0.25, 3}, big.size(), 0, 0, 0);
  xml.open("PointData");
  xml.array("empty", 1, std::vector<std::int32_t>{});
  xml.array("big", 1, big);
  xml.close("PointData");
  const std::string file = xml.finish();
  EXPECT_NE(file.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_NE(file.find("<DataArray type=\"Int32\" Name=\"empty\" format=\"appended\" offset=\"0\"/>"), std::string::npos);
  // The empty array is a header of no blocks: 3 x 8 bytes, so the next one starts at 24.
  EXPECT_NE(file.find("Name=\"big\" format=\"appended\" offset=\"24\"/>"), std::string::npos);
  const std::string raw = raw_data(file);
  EXPECT_EQ(u64(raw, 0), 0u);
  const std::size_t at = 24;
  ASSERT_EQ(u64(raw, at), 3u);                         // blocks
  EXPECT_EQ(u64(raw, at + 8), 32768u);                 // block size
  EXPECT_EQ(u64(raw, at + 16), 80000u - 2u * 32768u);  // the partial last block
  std::string bytes;
  std::size_t data = at + 24 + 3 * 8;
  for (std::size_t b = 0; b < 3; ++b) {
    const std::uint64_t compressed = u64(raw, at + 24 + 8 * b);
    uLongf size = 32768;
    std::string out(size, '\0');
    ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(raw.data() + data),
                         static_cast<uLong>(compressed)),
              Z_OK);
    bytes += out.substr(0, size);
    data += compressed;
  }
  ASSERT_EQ(bytes.size(), 80000u);
  EXPECT_EQ(std::memcmp(bytes.data(), big.data(), bytes.size()), 0);
  EXPECT_EQ(raw.substr(data - 0), "\n</AppendedData>\n</VTKFile>\n");
  // The field data stay inline text.
  EXPECT_NE(file.find("Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">\n0.25\n"), std::string::npos);
}

TEST(VtkXml, AsciiDoublesReadBackToTheSameBits) {
  const std::vector<double> values = {0.1 + 0.2, 1.0 / 3.0, -2.5e-310, 1e300, 123456789.123456789, -0.0};
  VtkXml xml(VtkEncoding::Ascii, {}, 2, 0, 0, 0);
  xml.open("PointData");
  xml.array("x", 3, values);
  xml.close("PointData");
  const std::string file = xml.finish();
  EXPECT_EQ(file.find("AppendedData"), std::string::npos);
  EXPECT_EQ(file.find("compressor"), std::string::npos);
  const std::string open = "NumberOfComponents=\"3\" format=\"ascii\">\n";
  const std::size_t from = file.find(open) + open.size();
  std::istringstream in(file.substr(from, file.find("</DataArray>", from) - from));
  std::vector<double> back;
  for (std::string word; in >> word;) back.push_back(std::strtod(word.c_str(), nullptr));
  ASSERT_EQ(back.size(), values.size());
  EXPECT_EQ(std::memcmp(back.data(), values.data(), values.size() * sizeof(double)), 0);
}

TEST(VtkXml, AnArrayOfPartTuplesIsRefused) {
  VtkXml xml(VtkEncoding::Binary, {}, 1, 0, 0, 0);
  EXPECT_THROW(xml.array("v", 3, std::vector<double>{1.0, 2.0}), std::invalid_argument);
}

}  // namespace
}  // namespace ratchet
