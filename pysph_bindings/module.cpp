// The compiled part of the Python package `consph`.
#include <pybind11/pybind11.h>

#include "Simulation/Common.h"

namespace py = pybind11;

PYBIND11_MODULE(_consph, m) {
  m.doc() = "consph: SPH fluids with consistent rigid-fluid coupling";
  m.attr("__version__") = CONSPH_VERSION;
  m.attr("precision") = consph::precisionName();
}
