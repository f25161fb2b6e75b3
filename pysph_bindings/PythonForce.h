// A non-pressure force written in Python. The C++ side is a trampoline: inside the step (GIL
// released) it takes the GIL, hands Python a StepContext and the fluid (zero-copy views), and
// calls add_acceleration(ctx, fluid), which adds to fluid.accelerations with NumPy. Its cost is
// that of its NumPy code plus a few microseconds for the call. A Python exception raised there
// aborts the step and reaches the caller of step()/run() unchanged.
#pragma once
#include "Simulation/NonPressureForce.h"
#include "pysph_bindings/PySimulation.h"

namespace consph::python {

class PythonForce final : public NonPressureForce {
 public:
  // `force`: an object with add_acceleration(ctx, fluid), or a callable(ctx, fluid).
  PythonForce(const py::object& force, std::weak_ptr<PySimulation> simulation);
  void addAccelerations(StepContext& ctx) override;

 private:
  SharedPyObject call_;  // the bound add_acceleration or the callable
  std::weak_ptr<PySimulation> simulation_;
};

// What a Python force sees of the step. It refers to the running step, so it expires when
// add_acceleration returns: a kept reference raises instead of reading freed data.
class PyStepContext {
 public:
  explicit PyStepContext(const StepContext& ctx) : ctx_(&ctx) {}
  const StepContext& get() const;
  void expire() { ctx_ = nullptr; }

 private:
  const StepContext* ctx_;
};

void bindForces(py::module_& m);

}  // namespace consph::python
