#include "state_arrays.hpp"

namespace py = pybind11;

namespace ratchet_python {
namespace {

static_assert(sizeof(ratchet::Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
static_assert(sizeof(ratchet::Quat) == 4 * sizeof(double), "Quat must be four packed doubles");

py::array view(const double* data, py::ssize_t rows, py::ssize_t columns, py::handle owner) {
  static const double empty = 0.0;  // numpy wants a pointer even for zero rows
  py::array a(py::dtype::of<double>(), {rows, columns},
              {static_cast<py::ssize_t>(columns * sizeof(double)), static_cast<py::ssize_t>(sizeof(double))},
              rows > 0 ? data : &empty, owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

}  // namespace

py::array vec3_view(const std::vector<ratchet::Vec3>& v, py::handle owner) {
  return view(v.empty() ? nullptr : v.front().data(), static_cast<py::ssize_t>(v.size()), 3, owner);
}

py::array quat_view(const std::vector<ratchet::Quat>& q, py::handle owner) {
  return view(q.empty() ? nullptr : q.front().coeffs().data(), static_cast<py::ssize_t>(q.size()), 4, owner);
}

}  // namespace ratchet_python
