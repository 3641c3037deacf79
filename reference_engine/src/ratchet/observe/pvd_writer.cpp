#include "ratchet/observe/pvd_writer.hpp"

#include <cmath>
#include <locale>
#include <sstream>
#include <stdexcept>

#include "ratchet/io/atomic_file.hpp"

namespace ratchet {
namespace {

// The characters that may not stand as they are in an XML attribute value.
std::string xml_attribute(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries) {
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (!std::isfinite(entries[i].time))
      throw std::invalid_argument("write_pvd: entry " + std::to_string(i) + ": time is not finite");
    if (entries[i].file.empty()) throw std::invalid_argument("write_pvd: entry " + std::to_string(i) + ": no file");
  }
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out.precision(17);
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "<Collection>\n";
  for (const PvdEntry& e : entries)
    out << "<DataSet timestep=\"" << e.time << "\" group=\"\" part=\"0\" file=\"" << xml_attribute(e.file)
        << "\"/>\n";
  out << "</Collection>\n</VTKFile>\n";
  write_file_atomic(path, out.str());
}

}  // namespace ratchet
