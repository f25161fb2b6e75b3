// A name-keyed table of plugin factories for one plugin interface (OpenFOAM's run-time
// selection, as a small template). A duplicate name is an error; an unknown name lists the
// valid ones; look-up ignores case, so "dfsph" finds "DFSPH".
#pragma once
#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "Simulation/Params.h"
#include "Utilities/Error.h"

namespace consph {

struct PluginContext;

template <class Base>
class Registry {
 public:
  using Factory = std::function<std::unique_ptr<Base>(const Params&, const PluginContext&)>;
  struct Entry {
    std::string name;
    std::string doc;
    std::vector<ParamSpec> params;
    Factory factory;
  };

  explicit Registry(std::string category) : category_(std::move(category)) {}

  void add(Entry entry) {
    if (find(entry.name)) throw std::logic_error(category_ + " '" + entry.name + "' is registered twice");
    entries_.push_back(std::move(entry));
    std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) { return a.name < b.name; });
  }

  const Entry* find(const std::string& name) const {
    for (auto& e : entries_)
      if (equalNoCase(e.name, name)) return &e;
    return nullptr;
  }

  const Entry& get(const std::string& name, const std::string& path) const {
    if (const Entry* e = find(name)) return *e;
    throw InputError(path + ": unknown " + category_ + " '" + name + "'; valid are: " + namesText());
  }

  // Creates the plugin named by object["type"] (or `typeName` when the object has none).
  std::unique_ptr<Base> create(const std::string& typeName, const json& object, const std::string& path,
                               const PluginContext& context, const LogSink& log) const {
    const Entry& e = get(typeName, path + ".type");
    Params params(object, path, e.params, log);
    return e.factory(params, context);
  }

  std::string namesText() const {
    std::string s;
    for (auto& e : entries_) s += (s.empty() ? "" : ", ") + e.name;
    return s.empty() ? "(none)" : s;
  }
  const std::vector<Entry>& entries() const { return entries_; }
  const std::string& category() const { return category_; }

 private:
  static bool equalNoCase(const std::string& a, const std::string& b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return std::tolower(x) == std::tolower(y); });
  }
  std::string category_;
  std::vector<Entry> entries_;
};

}  // namespace consph
