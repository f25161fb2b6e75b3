#include "Simulation/Params.h"

#include <cmath>
#include <sstream>

#include "Utilities/Error.h"

namespace consph {

const char* paramTypeName(ParamType t) {
  switch (t) {
    case ParamType::Real: return "number";
    case ParamType::Int: return "integer";
    case ParamType::Bool: return "boolean";
    case ParamType::String: return "string";
    case ParamType::Vector3: return "[x, y, z]";
  }
  return "?";
}

std::string ParamSpec::rangeText() const {
  std::ostringstream s;
  if (!choices.empty()) {
    s << "one of";
    for (auto& c : choices) s << " " << c;
    return s.str();
  }
  if (std::isinf(min) && std::isinf(max)) return "";
  s << "[" << (std::isinf(min) ? std::string("-inf") : json(min).dump()) << ", "
    << (std::isinf(max) ? std::string("inf") : json(max).dump()) << "]";
  return s.str();
}

namespace {
std::string typeOf(const json& v) {
  if (v.is_number()) return "number " + v.dump();
  if (v.is_string()) return "string " + v.dump();
  if (v.is_boolean()) return "boolean " + v.dump();
  if (v.is_array()) return "array " + v.dump();
  if (v.is_object()) return "object";
  return "null";
}
}  // namespace

void validateParam(const ParamSpec& spec, const json& v, const std::string& path) {
  auto fail = [&](const std::string& why) { throw InputError(path + ": " + why); };
  auto checkRange = [&](const json& number) {
    const double x = number.get<double>();
    if (!std::isfinite(x) || x < spec.min || x > spec.max)
      fail("value " + number.dump() + " is out of range " + spec.rangeText());
  };
  switch (spec.type) {
    case ParamType::Real:
      if (!v.is_number()) fail(std::string("expected a number, got ") + typeOf(v));
      checkRange(v);
      break;
    case ParamType::Int:
      if (!v.is_number_integer()) fail(std::string("expected an integer, got ") + typeOf(v));
      checkRange(v);
      break;
    case ParamType::Bool:
      if (!v.is_boolean()) fail(std::string("expected true or false, got ") + typeOf(v));
      break;
    case ParamType::String: {
      if (!v.is_string()) fail(std::string("expected a string, got ") + typeOf(v));
      if (!spec.choices.empty()) {
        const auto s = v.get<std::string>();
        bool ok = false;
        for (auto& c : spec.choices) ok |= (c == s);
        if (!ok) fail("'" + s + "' is not " + spec.rangeText());
      }
      break;
    }
    case ParamType::Vector3:
      if (!v.is_array() || v.size() != 3) fail(std::string("expected an array of 3 numbers, got ") + typeOf(v));
      for (auto& c : v) {
        if (!c.is_number()) fail(std::string("expected an array of 3 numbers, got ") + typeOf(v));
        checkRange(c);
      }
      break;
  }
}

Params::Params(const json& object, std::string path, std::vector<ParamSpec> specs, const LogSink& log,
               const std::vector<std::string>& ignoredKeys)
    : path_(std::move(path)), specs_(std::move(specs)), values_(json::object()), given_(json::object()) {
  if (!object.is_null() && !object.is_object()) throw InputError(path_ + ": expected an object, got " + typeOf(object));
  if (object.is_object()) {
    for (auto it = object.begin(); it != object.end(); ++it) {
      bool ignored = false;
      for (auto& k : ignoredKeys) ignored |= (k == it.key());
      if (ignored) continue;
      bool known = false;
      for (auto& s : specs_) known |= (s.name == it.key());
      if (!known) {
        // Every key this object takes: the declared ones and those the caller reads itself.
        std::string list;
        for (auto& s : specs_) list += (list.empty() ? "" : ", ") + s.name;
        for (auto& k : ignoredKeys) list += (list.empty() ? "" : ", ") + k;
        if (log) log(LogLevel::Warning, "unknown key '" + pathOf(it.key()) + "' ignored (known: " + (list.empty() ? "none" : list) + ")");
      }
    }
  }
  for (auto& s : specs_) {
    const json* v = nullptr;
    if (object.is_object()) {
      auto it = object.find(s.name);
      if (it != object.end()) v = &*it;
    }
    if (v) {
      validateParam(s, *v, pathOf(s.name));
      values_[s.name] = *v;
      given_[s.name] = true;
    } else if (s.defaultValue.is_null()) {
      throw InputError(pathOf(s.name) + ": required " + paramTypeName(s.type) + " is missing");
    } else {
      values_[s.name] = s.defaultValue;
    }
  }
}

const json& Params::value(const std::string& name, ParamType type) const {
  for (auto& s : specs_)
    if (s.name == name) {
      if (s.type != type) throw std::logic_error("parameter '" + name + "' read with the wrong type");
      return values_.at(name);
    }
  throw std::logic_error("parameter '" + name + "' read but never declared");
}

Real Params::real(const std::string& name) const { return value(name, ParamType::Real).get<Real>(); }
int Params::integer(const std::string& name) const { return value(name, ParamType::Int).get<int>(); }
bool Params::boolean(const std::string& name) const { return value(name, ParamType::Bool).get<bool>(); }
std::string Params::string(const std::string& name) const { return value(name, ParamType::String).get<std::string>(); }
Vector3r Params::vector3(const std::string& name) const {
  const json& v = value(name, ParamType::Vector3);
  return Vector3r(v[0].get<Real>(), v[1].get<Real>(), v[2].get<Real>());
}
bool Params::isSet(const std::string& name) const { return given_.contains(name); }

}  // namespace consph
