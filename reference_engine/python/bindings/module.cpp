// ratchet._engine: the engine's World for Python (docs/python.md). The package's
// reference_engine/python/ratchet/world.py wraps it; use that, not this module directly.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "contact_arrays.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/scene/scene.hpp"
#include "scene_input.hpp"
#include "state_arrays.hpp"
#include "stepped_world.hpp"

namespace py = pybind11;
using ratchet_python::SteppedWorld;

namespace {

const ratchet::World& of(const py::object& self) { return self.cast<const SteppedWorld&>().world(); }

py::dict stats(const ratchet::World& w) {
  const ratchet::StepStats& s = w.stats();
  py::dict d;
  d["contacts"] = s.contacts;
  d["iterations"] = s.iterations;
  d["residual"] = s.residual;
  d["converged"] = s.converged;
  d["wall_force_side"] = s.wall_force_side;
  d["wall_force_bottom"] = s.wall_force_bottom;
  d["wall_force_total"] = s.wall_force_total;
  d["max_overlap"] = s.max_overlap;
  return d;
}

}  // namespace

PYBIND11_MODULE(_engine, m) {
  m.doc() = "The ratchet engine's World (docs/python.md); use ratchet.World.";
  m.attr("version") = RATCHET_VERSION;
  m.attr("build_type") = RATCHET_BUILD_TYPE;
  // The scene reader's errors keep their message (file, field, what was expected).
  py::register_exception<ratchet::SceneError>(m, "SceneError", PyExc_ValueError);
  py::register_exception<ratchet::SettleError>(m, "SettleError", PyExc_RuntimeError);

  py::class_<SteppedWorld>(m, "World")
      .def_static(
          "from_file",
          [](const std::string& path, const std::vector<std::string>& overrides) {
            return std::make_unique<SteppedWorld>(ratchet_python::scene_from_file(path, overrides));
          },
          py::arg("path"), py::arg("overrides"))
      .def_static(
          "from_json",
          [](const std::string& text, const std::string& source, const std::vector<std::string>& overrides) {
            return std::make_unique<SteppedWorld>(ratchet_python::scene_from_json(text, source, overrides));
          },
          py::arg("text"), py::arg("source"), py::arg("overrides"))
      .def("step", &SteppedWorld::step, py::arg("n") = 1, py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("step_count", [](const py::object& self) { return of(self).state().step; })
      .def_property_readonly("steps", [](const py::object& self) { return of(self).scene().steps; })
      .def_property_readonly("t", [](const py::object& self) { return of(self).state().t; })
      .def_property_readonly("dt", [](const py::object& self) { return of(self).scene().dt; })
      .def_property_readonly("T", [](const py::object& self) { return of(self).state().T; })
      .def_property_readonly("s_p", [](const py::object& self) { return of(self).state().s_p; })
      .def_property_readonly("s_c", [](const py::object& self) { return of(self).state().s_c; })
      .def_property_readonly("settling", [](const py::object& self) { return of(self).settling(); })
      .def_property_readonly("name", [](const py::object& self) { return of(self).scene().name; })
      .def_property_readonly("scene_hash", [](const py::object& self) { return of(self).scene().hash; })
      .def_property_readonly("scene_json", [](const py::object& self) { return of(self).scene().as_run.dump(); })
      .def_property_readonly("kinetic_energy",
                             [](const py::object& self) { return ratchet::kinetic_energy(of(self).scene(), of(self).state()); })
      .def_property_readonly("positions",
                             [](const py::object& self) { return ratchet_python::vec3_view(of(self).state().x, self); })
      .def_property_readonly("velocities",
                             [](const py::object& self) { return ratchet_python::vec3_view(of(self).state().v, self); })
      .def_property_readonly("angular_velocities",
                             [](const py::object& self) { return ratchet_python::vec3_view(of(self).state().w, self); })
      .def_property_readonly("orientations_xyzw",
                             [](const py::object& self) { return ratchet_python::quat_view(of(self).state().q, self); })
      .def("stats", [](const py::object& self) { return stats(of(self)); })
      .def("contacts", [](const py::object& self) { return ratchet_python::contact_arrays(of(self)); });
}
