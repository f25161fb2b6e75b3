#include "pysph_bindings/PyFluid.h"

#include "pysph_bindings/FieldViews.h"
#include "pysph_bindings/PythonForce.h"

namespace consph::python {

namespace {

// Ids identify particles across re-sorting: writing them would break that.
bool writable(const FieldBase& field) { return field.name() != "id"; }

py::array view(const PyFluid& fluid, const std::string& name) {
  FieldBase* field = fluid.model().fields().find(name);
  if (!field) {
    std::string names;
    for (const auto& f : fluid.model().fields().all()) names += (names.empty() ? "" : ", ") + f->name();
    throw py::key_error("no particle field '" + name + "'; fields: " + names);
  }
  return fieldView(fluid.simulation, *field, writable(*field));
}

const char* typeName(FieldType type) {
  switch (type) {
    case FieldType::Scalar: return "scalar";
    case FieldType::Vector3: return "vector3";
    case FieldType::Index: return "index";
  }
  return "?";
}

}  // namespace

void bindFluid(py::module_& m) {
  py::class_<PyFluid>(m, "Fluid", R"doc(
One fluid's particles. Every array property returns a fresh zero-copy NumPy view of the C++ field
(shape (N,) or (N, 3), dtype float64/float32 per consph.precision, ids uint32). Views are writable
(ids are read-only); writing changes the simulation. The array's base keeps the simulation alive.

Rows are particles in memory order, which the Z-order sort permutes every simulation.sortInterval
steps (0: never): use `ids` to follow particles. A view kept across a change of the particle
count is stale (consph.is_current(view) is False; StaleViewWarning), and one whose storage moved
raises consph.StaleViewError: take fresh views after steps that may add particles.
)doc")
      .def_property_readonly("name", [](const PyFluid& f) { return f.model().name(); })
      .def_property_readonly("density0", [](const PyFluid& f) { return f.model().density0(); }, "rest density, kg/m^3")
      .def("__len__", [](const PyFluid& f) { return f.model().size(); })
      .def_property_readonly("size", [](const PyFluid& f) { return f.model().size(); }, "number of particles")
      .def_property_readonly("positions", [](const PyFluid& f) { return view(f, "position"); }, "(N, 3) x_i, m")
      .def_property_readonly("velocities", [](const PyFluid& f) { return view(f, "velocity"); }, "(N, 3) v_i, m/s")
      .def_property_readonly("accelerations", [](const PyFluid& f) { return view(f, "acceleration"); },
                             "(N, 3) non-pressure acceleration a_i^np, m/s^2 (gravity + forces; a Force adds to it)")
      .def_property_readonly("densities", [](const PyFluid& f) { return view(f, "density"); },
                             "(N,) rho_i, kg/m^3 (recomputed every step)")
      .def_property_readonly(
          "pressures",
          [](const PyFluid& f) {
            f.simulation->simulation().updatePressureField();
            return view(f, "pressure");
          },
          "(N,) the pressure field at each particle, Pa: the kernel average of the solver's pressures over its "
          "neighbourhood (Simulation::updatePressureField), computed when read after a step")
      .def_property_readonly("solver_pressures", [](const PyFluid& f) { return view(f, "solverPressure"); },
                             "(N,) p_i as the pressure solver found it (field solverPressure), Pa: the per-particle "
                             "multiplier, which scatters by about rho0 g times one spacing around the field")
      .def_property_readonly("masses", [](const PyFluid& f) { return view(f, "mass"); }, "(N,) m_i, kg")
      .def_property_readonly("ids", [](const PyFluid& f) { return view(f, "id"); },
                             "(N,) stable particle ids (read-only): rows are re-sorted, ids are not")
      .def("field", &view, py::arg("name"), "A view of any registered field by name (see fields()).")
      .def("__getitem__", &view, py::arg("name"))
      .def("__contains__", [](const PyFluid& f, const std::string& name) { return f.model().fields().has(name); })
      .def(
          "fields",
          [](const PyFluid& f) {
            py::dict out;
            for (const auto& field : f.model().fields().all()) {
              py::list flags;
              if (field->flags() & FieldSorted) flags.append("sorted");
              if (field->flags() & FieldExported) flags.append("exported");
              out[py::str(field->name())] = py::dict(py::arg("type") = typeName(field->type()),
                                                     py::arg("flags") = flags, py::arg("writable") = writable(*field));
            }
            return out;
          },
          "Every registered particle field: {name: {type, flags, writable}} (plugins add their own).")
      .def(
          "add_force",
          [](const PyFluid& f, py::object force) {
            f.simulation->requireIdle();
            f.simulation->simulation().addForce(std::make_unique<PythonForce>(force, f.simulation));
            return force;
          },
          py::arg("force"), R"doc(
Attaches a force written in Python: a consph.Force (add_acceleration(ctx, fluid)) or any
callable(ctx, fluid). It runs inside every step after the scene's forces, where non-pressure
forces run (before the pressure solve), and adds to fluid.accelerations. Returns the force.)doc")
      .def("_resize", [](const PyFluid& f, std::size_t n) { f.simulation->resizeForTesting(n); }, py::arg("n"),
           "Testing only: changes the particle count (stand-in for emitters).")
      .def("__repr__", [](const PyFluid& f) {
        return "<consph.Fluid '" + f.model().name() + "': " + std::to_string(f.model().size()) + " particles>";
      });
}

}  // namespace consph::python
