#include "pysph_bindings/PythonForce.h"

#include <pybind11/numpy.h>

#include "pysph_bindings/FieldViews.h"
#include "pysph_bindings/PyFluid.h"

namespace consph::python {

PythonForce::PythonForce(const py::object& force, std::weak_ptr<PySimulation> simulation)
    : simulation_(std::move(simulation)) {
  if (py::hasattr(force, "add_acceleration")) call_ = sharePyObject(force.attr("add_acceleration"));
  else if (PyCallable_Check(force.ptr())) call_ = sharePyObject(force);
  else
    throw py::type_error("a force must be a consph.Force (with add_acceleration(ctx, fluid)) or a callable(ctx, fluid), not " +
                         std::string(py::str(force.get_type().attr("__name__"))));
}

void PythonForce::addAccelerations(StepContext& ctx) {
  py::gil_scoped_acquire gil;
  const std::shared_ptr<PySimulation> simulation = simulation_.lock();  // alive: it is stepping
  if (!simulation) throw SimulationError("a Python force ran without its simulation");
  auto context = std::make_shared<PyStepContext>(ctx);
  struct Expire {
    PyStepContext& c;
    ~Expire() { c.expire(); }
  } expire{*context};
  (*call_)(context, PyFluid{simulation});
}

const StepContext& PyStepContext::get() const {
  if (!ctx_) throw std::runtime_error("this StepContext belongs to a finished step: use the ctx passed to add_acceleration only during that call");
  return *ctx_;
}

namespace {

// Kernel values for an array of distances, gradients for an (n, 3) array of x_i - x_j.
py::array kernelW(const PyStepContext& c, const py::array_t<Real, py::array::c_style | py::array::forcecast>& r) {
  const CubicSplineKernel& k = c.get().kernel;
  py::array_t<Real> out(r.request().shape);
  const Real* in = r.data();
  Real* o = out.mutable_data();
  for (py::ssize_t i = 0; i < r.size(); ++i) o[i] = k.W(in[i]);
  return out;
}

py::array kernelGradW(const PyStepContext& c, const py::array_t<Real, py::array::c_style | py::array::forcecast>& x) {
  if (x.ndim() != 2 || x.shape(1) != 3) throw py::value_error("kernel_grad_w: expected an (n, 3) array of x_i - x_j");
  const CubicSplineKernel& k = c.get().kernel;
  py::array_t<Real> out({x.shape(0), py::ssize_t(3)});
  const Real* in = x.data();
  Real* o = out.mutable_data();
  for (py::ssize_t i = 0; i < x.shape(0); ++i) {
    const Vector3r g = k.gradW(Vector3r(in[3 * i], in[3 * i + 1], in[3 * i + 2]));
    for (int a = 0; a < 3; ++a) o[3 * i + a] = g[a];
  }
  return out;
}

py::tuple neighbours(const NeighborLists& lists) {
  return py::make_tuple(copyToNumpy(lists.offsets), copyToNumpy(lists.indices));
}

}  // namespace

void bindForces(py::module_& m) {
  py::class_<PyStepContext, std::shared_ptr<PyStepContext>>(m, "StepContext", R"doc(
The running step, as a Python force sees it (valid only during add_acceleration).
Neighbour lists and boundary samples are rebuilt every step, so their accessors return copies.
)doc")
      .def_property_readonly("dt", [](const PyStepContext& c) { return c.get().dt; },
                             "time step, s (the previous step's: the CFL step is chosen after the forces)")
      .def_property_readonly("time", [](const PyStepContext& c) { return c.get().time; }, "simulated time, s")
      .def_property_readonly("step", [](const PyStepContext& c) { return c.get().step; }, "steps done so far")
      .def_property_readonly("gravity", [](const PyStepContext& c) {
        py::array_t<Real> g(3);
        for (int a = 0; a < 3; ++a) g.mutable_at(a) = c.get().gravity[a];
        return g;
      })
      .def_property_readonly("particle_radius", [](const PyStepContext& c) { return c.get().particleRadius; })
      .def_property_readonly("support_radius", [](const PyStepContext& c) { return c.get().kernel.supportRadius(); })
      .def("fluid_neighbors", [](const PyStepContext& c) { return neighbours(c.get().fluidNeighbors); },
           "(offsets, indices): the neighbours j != i of particle i are indices[offsets[i]:offsets[i+1]] (copies)")
      .def("boundary_neighbors", [](const PyStepContext& c) { return neighbours(c.get().boundaryNeighbors); },
           "(offsets, indices) into the boundary samples, as fluid_neighbors (copies)")
      .def("boundary_positions", [](const PyStepContext& c) { return copyToNumpy(c.get().boundary.positions); })
      .def("boundary_velocities", [](const PyStepContext& c) { return copyToNumpy(c.get().boundary.velocities); })
      .def("boundary_masses", [](const PyStepContext& c) { return copyToNumpy(c.get().boundary.masses); },
           "rho0 V_k, kg")
      .def("kernel_w", &kernelW, py::arg("r"), "cubic spline W(r) for an array of distances")
      .def("kernel_grad_w", &kernelGradW, py::arg("x"), "grad W(x) for an (n, 3) array of x_i - x_j");
}

}  // namespace consph::python
