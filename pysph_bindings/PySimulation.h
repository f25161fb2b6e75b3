// The Python-side owner of one Simulation. Python holds it through a shared_ptr, and so does the
// base object of every NumPy view of its particles (MuJoCo's pattern): an array outlives `del sim`.
// Stepping runs with the GIL released; log messages queue up meanwhile and reach Python
// (warnings.warn, logging or a user callback) once the GIL is back, so C++ never calls into Python
// from inside a step except through a Python force, which takes the GIL itself.
#pragma once
#include <pybind11/pybind11.h>

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <unordered_set>

#include "Simulation/Simulation.h"

namespace consph {
class Progress;
}

namespace consph::python {

namespace py = pybind11;

class FieldViewOwner;
class PythonPlugins;

// A Python object that C++ may copy and drop without holding the GIL (plugin tables are copied
// inside the Simulation's constructor, which runs with the GIL released): the last owner takes
// the GIL to release it.
using SharedPyObject = std::shared_ptr<py::object>;
SharedPyObject sharePyObject(py::object object);

// Particle storage moved while NumPy views of it were alive (they would dangle).
struct StaleViewError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class PySimulation : public std::enable_shared_from_this<PySimulation> {
 public:
  // Parses `scene` (resolving relative paths against `baseDir`) and builds the simulation with
  // the built-in plugins plus `plugins`' Python forces. `log`: None (warnings go to
  // warnings.warn, info to logging.getLogger("consph")) or callable(level: str, message: str).
  // `restartFrom`: a checkpoint of the same scene to continue from (empty: start at t = 0).
  // A scene in SPlisHSPlasH's layout is first converted to the consph scene it maps to (as the
  // CLI runs it, its warnings through `log`; `name`: the converted scene's name), and then
  // `options` (the keyword arguments' overrides and output) apply to that consph scene.
  static std::shared_ptr<PySimulation> create(const json& scene, const std::string& baseDir, const PythonPlugins& plugins,
                                              py::object log, const std::string& restartFrom = "",
                                              const std::function<json(json)>& options = {}, const std::string& name = "");
  ~PySimulation();

  // The simulation, for reading and writing between steps (or from inside a Python force on
  // the stepping thread); other threads get an error while a step runs.
  Simulation& simulation();
  // Steps `n` times / until simulated time `until`, with the GIL released. Returns to Python
  // every 0.2 s of wall time (Ctrl-C works) and after every step when `perStep` is a callable.
  void step(std::size_t n);
  void run(double until, py::object progress);
  void exportFrame(const std::string& path);
  // Errors unless no step is running (adding a force from inside a step would be unsafe).
  void requireIdle() const;

  // Views register themselves so that a change of the particle storage can be reported:
  // storage that moved -> StaleViewError; only the count changed -> StaleViewWarning.
  void addView(FieldViewOwner* view) { views_.insert(view); }
  void removeView(FieldViewOwner* view) { views_.erase(view); }
  void checkViews(bool raise);
  // Changes the particle count (new particles get each field's initial value): only for
  // testing the stale-view checks until emitters exist.
  void resizeForTesting(std::size_t n);

 private:
  PySimulation() = default;
  // Runs f with the GIL released, then delivers queued log messages and checks views.
  template <class F>
  void released(F&& f);
  void advance(const std::function<bool()>& done, const py::object& perStep, Progress* bar);
  void flushLog();

  std::unique_ptr<Simulation> simulation_;
  py::object logCallback_;
  std::mutex logMutex_;
  std::vector<std::pair<LogLevel, std::string>> pendingLog_;
  std::atomic<bool> busy_{false};
  std::thread::id busyThread_;
  std::unordered_set<FieldViewOwner*> views_;
};

void bindSimulation(py::module_& m);

}  // namespace consph::python
