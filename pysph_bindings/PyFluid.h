// The Python view of one fluid: its particle fields as zero-copy NumPy arrays (FieldViews.h) and
// the forces attached to it.
#pragma once
#include "pysph_bindings/PySimulation.h"

namespace consph::python {

struct PyFluid {
  std::shared_ptr<PySimulation> simulation;
  FluidModel& model() const { return simulation->simulation().fluid(); }
};

void bindFluid(py::module_& m);

}  // namespace consph::python
