#include "contact_arrays.hpp"

#include <pybind11/numpy.h>

namespace py = pybind11;

namespace ratchet_python {

py::dict contact_arrays(const ratchet::World& world) {
  const auto& contacts = world.contacts();
  const auto n = static_cast<py::ssize_t>(contacts.size());
  const double h = world.scene().dt;
  py::array_t<int> a(n), b(n);
  py::array_t<double> point({n, py::ssize_t{3}}), normal({n, py::ssize_t{3}}), impulse({n, py::ssize_t{3}}),
      force({n, py::ssize_t{3}});
  py::array_t<double> gap(n), mu(n);
  auto ra = a.mutable_unchecked<1>(), rb = b.mutable_unchecked<1>();
  auto rp = point.mutable_unchecked<2>(), rn = normal.mutable_unchecked<2>(), ri = impulse.mutable_unchecked<2>(),
       rf = force.mutable_unchecked<2>();
  auto rg = gap.mutable_unchecked<1>(), rm = mu.mutable_unchecked<1>();
  for (py::ssize_t k = 0; k < n; ++k) {
    const ratchet::SolverContact& c = contacts[static_cast<std::size_t>(k)];
    ra(k) = c.a;
    rb(k) = c.b;
    rg(k) = c.geometry.gap;
    rm(k) = c.mu;
    const ratchet::Vec3 f = (c.lambda[0] * c.geometry.normal + c.lambda[1] * c.t1 + c.lambda[2] * c.t2) / h;
    for (py::ssize_t d = 0; d < 3; ++d) {
      rp(k, d) = c.geometry.point[d];
      rn(k, d) = c.geometry.normal[d];
      ri(k, d) = c.lambda[d];
      rf(k, d) = f[d];
    }
  }
  py::dict out;
  out["a"] = a;
  out["b"] = b;
  out["point"] = point;
  out["normal"] = normal;
  out["gap"] = gap;
  out["mu"] = mu;
  out["impulse"] = impulse;
  out["force"] = force;
  return out;
}

}  // namespace ratchet_python
