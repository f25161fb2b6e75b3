#include "pysph_bindings/FieldViews.h"

namespace consph::python {

static_assert(sizeof(Vector3r) == 3 * sizeof(Real), "Vector3r must be three packed Reals to map onto NumPy (N, 3)");

FieldViewOwner::FieldViewOwner(std::shared_ptr<PySimulation> simulation, std::string field, const void* data,
                               std::size_t rows)
    : simulation_(std::move(simulation)), field_(std::move(field)), data_(data), rows_(rows) {
  simulation_->addView(this);
}

FieldViewOwner::~FieldViewOwner() { simulation_->removeView(this); }

bool FieldViewOwner::isCurrent() const {
  FluidModel& fluid = simulation_->simulation().fluid();
  FieldBase* field = fluid.fields().find(field_);
  return field && field->data() == data_ && fluid.size() == rows_;
}

namespace {

py::dtype dtypeOf(FieldType type) { return type == FieldType::Index ? py::dtype::of<Index>() : py::dtype::of<Real>(); }

std::vector<py::ssize_t> shapeOf(FieldType type, std::size_t rows) {
  if (type == FieldType::Vector3) return {py::ssize_t(rows), 3};
  return {py::ssize_t(rows)};
}

std::vector<py::ssize_t> stridesOf(FieldType type) {
  if (type == FieldType::Vector3) return {py::ssize_t(sizeof(Vector3r)), py::ssize_t(sizeof(Real))};
  return {py::ssize_t(type == FieldType::Index ? sizeof(Index) : sizeof(Real))};
}

template <class T>
py::array copyOf(std::span<const T> values, FieldType type) {
  py::array out(dtypeOf(type), shapeOf(type, values.size()), stridesOf(type));
  if (!values.empty()) std::memcpy(out.mutable_data(), values.data(), values.size() * sizeof(T));
  return out;
}

}  // namespace

py::array fieldView(const std::shared_ptr<PySimulation>& simulation, FieldBase& field, bool writable) {
  const std::size_t rows = simulation->simulation().fluid().size();
  if (field.size() < rows) throw std::logic_error("particle field '" + field.name() + "' is shorter than the particle count");
  py::object base = py::cast(std::make_unique<FieldViewOwner>(simulation, field.name(), field.data(), rows));
  py::array view(dtypeOf(field.type()), shapeOf(field.type(), rows), stridesOf(field.type()), field.data(), base);
  if (!writable) py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

py::array copyToNumpy(std::span<const Real> values) { return copyOf(values, FieldType::Scalar); }
py::array copyToNumpy(std::span<const Index> values) { return copyOf(values, FieldType::Index); }
py::array copyToNumpy(std::span<const Vector3r> values) { return copyOf(values, FieldType::Vector3); }

void bindFieldViews(py::module_& m) {
  py::class_<FieldViewOwner>(m, "FieldViewOwner", R"doc(
The `base` of every particle array: keeps the Simulation alive and remembers the particle storage
and count the view was made for. consph.is_current(array) checks it.
)doc")
      .def_property_readonly("field", &FieldViewOwner::field)
      .def_property_readonly("rows", &FieldViewOwner::rows)
      .def_property_readonly("simulation", &FieldViewOwner::simulation)
      .def("is_current", &FieldViewOwner::isCurrent);
}

}  // namespace consph::python
