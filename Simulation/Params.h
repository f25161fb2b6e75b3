// Plugin parameters: each plugin declares its parameters (name, type, default, range, one-line
// doc); a Params object validates a scene's JSON object against them once, at creation, and then
// answers typed look-ups. Errors name the JSON path; unknown keys are reported as warnings.
#pragma once
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "Simulation/Common.h"
#include "Utilities/Log.h"

namespace consph {

using json = nlohmann::json;

enum class ParamType { Real, Int, Bool, String, Vector3 };
const char* paramTypeName(ParamType t);

struct ParamSpec {
  std::string name;
  ParamType type;
  json defaultValue;  // null: required
  std::string doc;
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  std::vector<std::string> choices = {};  // for String: the accepted values (empty: any)

  std::string rangeText() const;
};

class Params {
 public:
  Params() = default;
  // Validates `object` (whose JSON path is `path`) against `specs`; `ignoredKeys` are keys the
  // caller handles itself (e.g. "type"). Throws InputError on a wrong type or range.
  Params(const json& object, std::string path, std::vector<ParamSpec> specs, const LogSink& log,
         const std::vector<std::string>& ignoredKeys = {"type"});

  Real real(const std::string& name) const;
  int integer(const std::string& name) const;
  bool boolean(const std::string& name) const;
  std::string string(const std::string& name) const;
  Vector3r vector3(const std::string& name) const;
  bool isSet(const std::string& name) const;  // given in the scene (not defaulted)
  const std::string& path() const { return path_; }
  std::string pathOf(const std::string& name) const { return path_.empty() ? name : path_ + "." + name; }
  const json& values() const { return values_; }

 private:
  const json& value(const std::string& name, ParamType type) const;
  std::string path_;
  std::vector<ParamSpec> specs_;
  json values_;  // validated values, defaults filled in
  json given_;
};

// A parameter check shared by plugins and the scene reader.
void validateParam(const ParamSpec& spec, const json& value, const std::string& path);

}  // namespace consph
