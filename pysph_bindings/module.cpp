// The compiled part of the Python package `consph` (the Python part is consph/__init__.py).
// Each concept binds itself: PySimulation (load, step, run), PyFluid + FieldViews (zero-copy
// arrays), PythonForce (forces written in Python), PythonPlugins (the registry).
#include <pybind11/pybind11.h>

#include "Simulation/Common.h"
#include "Utilities/Error.h"
#include "pysph_bindings/FieldViews.h"
#include "pysph_bindings/PyFluid.h"
#include "pysph_bindings/PythonForce.h"
#include "pysph_bindings/PythonPlugins.h"

namespace py = pybind11;
using namespace consph::python;

PYBIND11_MODULE(_consph, m) {
  m.doc() = "consph: SPH fluids with consistent rigid-fluid coupling";
  m.attr("__version__") = CONSPH_VERSION;
  m.attr("precision") = consph::precisionName();

  // The CLI's error classes, with its messages: bad input, and a simulation that blew up.
  py::register_exception<consph::InputError>(m, "SceneError", PyExc_ValueError);
  py::register_exception<consph::SimulationError>(m, "SimulationError", PyExc_RuntimeError);
  py::register_exception<consph::OutputError>(m, "OutputError", PyExc_OSError);
  py::register_exception<StaleViewError>(m, "StaleViewError", PyExc_RuntimeError);
  const py::object warning = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "consph.ConsphWarning", "Warnings of a consph simulation (unknown scene keys, solver iteration cap, ...).",
      PyExc_UserWarning, nullptr));
  m.attr("ConsphWarning") = warning;
  m.attr("StaleViewWarning") = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "consph.StaleViewWarning", "A NumPy view was made for a different particle count.", warning.ptr(), nullptr));

  bindFieldViews(m);
  bindFluid(m);
  bindForces(m);
  bindPlugins(m);
  bindSimulation(m);
}
