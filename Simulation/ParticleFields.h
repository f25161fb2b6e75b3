// Named, structure-of-arrays particle fields. Every field is one contiguous std::vector, so it
// maps 1:1 onto a NumPy view; flags tell sorting and export what to do with it, so a field a
// plugin registers is re-sorted, exported and visible from Python without plugin-specific code.
#pragma once
#include <algorithm>
#include <memory>
#include <string>
#include <typeinfo>
#include <vector>

#include "Simulation/Common.h"
#include "Utilities/Error.h"

namespace consph {

enum class FieldType { Scalar, Vector3, Index };

enum FieldFlags : unsigned {
  FieldNone = 0,
  FieldSorted = 1u << 0,    // permuted with the particles on Z-order sorting
  FieldExported = 1u << 1,  // written to every output frame
};

class FieldBase {
 public:
  FieldBase(std::string name, FieldType type, unsigned flags) : name_(std::move(name)), type_(type), flags_(flags) {}
  virtual ~FieldBase() = default;
  const std::string& name() const { return name_; }
  FieldType type() const { return type_; }
  unsigned flags() const { return flags_; }
  void setFlags(unsigned flags) { flags_ = flags; }
  int components() const { return type_ == FieldType::Vector3 ? 3 : 1; }
  virtual void* data() = 0;
  virtual std::size_t size() const = 0;
  virtual void resize(std::size_t n) = 0;
  virtual void reserve(std::size_t n) = 0;
  // values[i] = old[order[i]] for i < order.size(); entries past order.size() stay.
  virtual void permute(const std::vector<Index>& order) = 0;

 private:
  std::string name_;
  FieldType type_;
  unsigned flags_;
};

template <class T>
struct FieldTypeOf;
template <>
struct FieldTypeOf<Real> { static constexpr FieldType value = FieldType::Scalar; };
template <>
struct FieldTypeOf<Vector3r> { static constexpr FieldType value = FieldType::Vector3; };
template <>
struct FieldTypeOf<Index> { static constexpr FieldType value = FieldType::Index; };

template <class T>
class Field final : public FieldBase {
 public:
  Field(std::string name, unsigned flags, std::size_t n, const T& initial)
      : FieldBase(std::move(name), FieldTypeOf<T>::value, flags), values(n, initial), initial_(initial) {}
  void* data() override { return values.data(); }
  std::size_t size() const override { return values.size(); }
  void resize(std::size_t n) override { values.resize(n, initial_); }
  void reserve(std::size_t n) override { values.reserve(n); }
  void permute(const std::vector<Index>& order) override {
    scratch_.resize(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) scratch_[i] = values[order[i]];
    std::copy(scratch_.begin(), scratch_.end(), values.begin());
  }
  std::vector<T> values;

 private:
  T initial_;
  std::vector<T> scratch_;
};

class ParticleFields {
 public:
  // Registers a field, or returns the existing one of the same name and type (two plugins may
  // share a field such as normals). The reference stays valid for the lifetime of this object.
  template <class T>
  std::vector<T>& add(const std::string& name, unsigned flags, const T& initial = T()) {
    if (FieldBase* existing = find(name)) {
      if (existing->type() != FieldTypeOf<T>::value)
        throw InputError("particle field '" + name + "' is already registered with another type");
      existing->setFlags(existing->flags() | flags);
      return static_cast<Field<T>*>(existing)->values;
    }
    auto field = std::make_unique<Field<T>>(name, flags, size_, initial);
    field->reserve(capacity_);
    auto& values = field->values;
    fields_.push_back(std::move(field));
    return values;
  }

  template <class T>
  std::vector<T>& get(const std::string& name) {
    FieldBase* f = find(name);
    if (!f || f->type() != FieldTypeOf<T>::value) throw InputError("no particle field '" + name + "' of the requested type");
    return static_cast<Field<T>*>(f)->values;
  }

  FieldBase* find(const std::string& name) {
    for (auto& f : fields_)
      if (f->name() == name) return f.get();
    return nullptr;
  }
  bool has(const std::string& name) const {
    for (auto& f : fields_)
      if (f->name() == name) return true;
    return false;
  }

  // Within a reserved capacity no field reallocates, so data pointers (NumPy views) stay valid.
  void resize(std::size_t n) {
    if (capacity_ > 0 && n > capacity_)
      throw SimulationError("particle budget exceeded: " + std::to_string(n) + " particles, " + std::to_string(capacity_) +
                            " reserved");
    size_ = n;
    for (auto& f : fields_) f->resize(n);
  }
  std::size_t size() const { return size_; }

  // Reserves room for `capacity` particles in every field, present and future (emitters reserve
  // their whole budget up front). After this, resize() beyond the capacity is an error.
  void reserve(std::size_t capacity) {
    capacity_ = std::max(capacity, size_);
    for (auto& f : fields_) f->reserve(capacity_);
  }
  std::size_t capacity() const { return capacity_; }

  // Keeps particles keep[0], keep[1], ... (increasing indices) in that order and drops the rest:
  // every field, sorted or not, so no field keeps values of a removed particle.
  void compact(const std::vector<Index>& keep) {
    for (auto& f : fields_) f->permute(keep);
    resize(keep.size());
  }

  void permuteSorted(const std::vector<Index>& order) {
    for (auto& f : fields_)
      if (f->flags() & FieldSorted) f->permute(order);
  }

  const std::vector<std::unique_ptr<FieldBase>>& all() const { return fields_; }

 private:
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;  // 0: not reserved, fields grow freely
  std::vector<std::unique_ptr<FieldBase>> fields_;
};

}  // namespace consph
