#include "ratchet/observe/vtk_xml.hpp"

#include <zlib.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace ratchet {
namespace {

// The files declare byte_order="LittleEndian" and carry values as they are in memory.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the VTK writer assumes a little-endian machine");

// VTK's own block size (vtkXMLWriter's default): any reader that reads VTK's files
// reads these.
constexpr std::size_t kBlockBytes = 32768;

template <class T>
void put_number(std::string& out, T x) {
  char buf[32];
  // Shortest form that reads back to the same value (doubles) or the integer as is.
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, r.ptr);
}

void put_u64(std::string& out, std::uint64_t x) {
  char b[8];
  std::memcpy(b, &x, 8);
  out.append(b, 8);
}

// `bytes` as VTK's compressed binary data: the UInt64 header and the zlib blocks.
std::string compressed(const char* bytes, std::size_t size) {
  const std::size_t blocks = (size + kBlockBytes - 1) / kBlockBytes;
  std::string header, data;
  put_u64(header, blocks);
  put_u64(header, kBlockBytes);
  put_u64(header, size % kBlockBytes);  // the last block's size when it is partial, else 0
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t n = std::min(kBlockBytes, size - b * kBlockBytes);
    uLongf out_size = compressBound(static_cast<uLong>(n));
    std::string block(out_size, '\0');
    if (compress2(reinterpret_cast<Bytef*>(block.data()), &out_size,
                  reinterpret_cast<const Bytef*>(bytes + b * kBlockBytes), static_cast<uLong>(n),
                  Z_DEFAULT_COMPRESSION) != Z_OK)
      throw std::runtime_error("VTK writer: zlib could not compress a data array");
    put_u64(header, out_size);
    data.append(block.data(), out_size);
  }
  return header + data;
}

}  // namespace

const char* vtk_encoding_name(VtkEncoding e) { return e == VtkEncoding::Ascii ? "ascii" : "binary"; }

VtkXml::VtkXml(VtkEncoding encoding, const VtkTime& time, std::size_t points, std::size_t verts, std::size_t lines,
               std::size_t polys)
    : encoding_(encoding) {
  text_ = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
          "header_type=\"UInt64\"";
  if (encoding_ == VtkEncoding::Binary) text_ += " compressor=\"vtkZLibDataCompressor\"";
  text_ += ">\n<PolyData>\n<FieldData>\n";
  text_ += "<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">\n";
  put_number(text_, time.t);
  text_ += "\n</DataArray>\n<DataArray type=\"Int64\" Name=\"step\" NumberOfTuples=\"1\" format=\"ascii\">\n";
  put_number(text_, time.step);
  text_ += "\n</DataArray>\n</FieldData>\n<Piece NumberOfPoints=\"" + std::to_string(points) +
           "\" NumberOfVerts=\"" + std::to_string(verts) + "\" NumberOfLines=\"" + std::to_string(lines) +
           "\" NumberOfStrips=\"0\" NumberOfPolys=\"" + std::to_string(polys) + "\">\n";
}

void VtkXml::open(const char* section) { text_ += std::string("<") + section + ">\n"; }
void VtkXml::close(const char* section) { text_ += std::string("</") + section + ">\n"; }

template <class T>
void VtkXml::add(const char* type, const char* name, int components, const std::vector<T>& values) {
  if (components < 1 || values.size() % static_cast<std::size_t>(components) != 0)
    throw std::invalid_argument(std::string("VTK writer: array ") + name + " is not whole tuples");
  text_ += std::string("<DataArray type=\"") + type + "\" Name=\"" + name + '"';
  if (components > 1) text_ += " NumberOfComponents=\"" + std::to_string(components) + '"';
  if (encoding_ == VtkEncoding::Binary) {
    text_ += " format=\"appended\" offset=\"" + std::to_string(appended_.size()) + "\"/>\n";
    appended_ += compressed(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    return;
  }
  text_ += " format=\"ascii\">\n";
  for (std::size_t i = 0; i < values.size(); ++i) {
    put_number(text_, values[i]);
    text_ += (i + 1) % static_cast<std::size_t>(components) == 0 ? '\n' : ' ';
  }
  text_ += "</DataArray>\n";
}

void VtkXml::array(const char* name, int components, const std::vector<double>& values) {
  add("Float64", name, components, values);
}
void VtkXml::array(const char* name, int components, const std::vector<std::int32_t>& values) {
  add("Int32", name, components, values);
}
void VtkXml::array(const char* name, int components, const std::vector<std::int64_t>& values) {
  add("Int64", name, components, values);
}

std::string VtkXml::finish() {
  text_ += "</Piece>\n</PolyData>\n";
  if (encoding_ == VtkEncoding::Binary) {
    // "_" marks the start of the raw bytes; the offsets count from after it.
    text_ += "<AppendedData encoding=\"raw\">\n_";
    text_ += appended_;
    text_ += "\n</AppendedData>\n";
    appended_.clear();
  }
  text_ += "</VTKFile>\n";
  return std::move(text_);
}

}  // namespace ratchet
