// Zero-copy NumPy views of particle fields. Every view's base is a FieldViewOwner, which holds
// the simulation (shared_ptr) and remembers the storage and row count the view was made for:
//  - `fluid.positions` (and every field accessor) returns a fresh view of the current particles;
//  - a view kept across steps keeps seeing the live data while the particle count is unchanged
//    (rows are permuted by the Z-order sort every simulation.sortInterval steps: use `ids`);
//  - when the count changes (emitters), old views are stale: consph.is_current(view) is False
//    and a StaleViewWarning is issued; if the storage itself moved, keeping the view would
//    dangle, so the step raises consph.StaleViewError instead.
#pragma once
#include <pybind11/numpy.h>

#include <span>

#include "pysph_bindings/PySimulation.h"

namespace consph::python {

class FieldViewOwner {
 public:
  FieldViewOwner(std::shared_ptr<PySimulation> simulation, std::string field, const void* data, std::size_t rows);
  ~FieldViewOwner();
  FieldViewOwner(const FieldViewOwner&) = delete;
  FieldViewOwner& operator=(const FieldViewOwner&) = delete;

  const std::string& field() const { return field_; }
  const void* data() const { return data_; }
  std::size_t rows() const { return rows_; }
  const std::shared_ptr<PySimulation>& simulation() const { return simulation_; }
  // The field still lives at the same address with the same particle count.
  bool isCurrent() const;
  bool reported = false;  // stale-ness reported once

 private:
  std::shared_ptr<PySimulation> simulation_;
  std::string field_;
  const void* data_;
  std::size_t rows_;
};

// A view of `field` with one row per particle: (N,) for scalars and ids, (N, 3) for vectors.
py::array fieldView(const std::shared_ptr<PySimulation>& simulation, FieldBase& field, bool writable);

// Copies for data that is rebuilt every step (neighbour lists, boundary samples).
py::array copyToNumpy(std::span<const Real> values);
py::array copyToNumpy(std::span<const Index> values);
py::array copyToNumpy(std::span<const Vector3r> values);

void bindFieldViews(py::module_& m);

}  // namespace consph::python
