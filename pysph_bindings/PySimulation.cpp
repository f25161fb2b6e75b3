#include "pysph_bindings/PySimulation.h"

#include <omp.h>

#include <cmath>
#include <filesystem>

#include "Simulation/SceneFile.h"
#include "Simulation/SplishSplashScene.h"
#include "Utilities/Progress.h"
#include "Utilities/ThreadCount.h"
#include "Utilities/Timer.h"
#include "pysph_bindings/FieldViews.h"
#include "pysph_bindings/JsonConversion.h"
#include "pysph_bindings/PyFluid.h"
#include "pysph_bindings/PythonPlugins.h"

namespace consph::python {

SharedPyObject sharePyObject(py::object object) {
  return SharedPyObject(new py::object(std::move(object)), [](py::object* p) {
    py::gil_scoped_acquire gil;
    delete p;
  });
}

std::shared_ptr<PySimulation> PySimulation::create(const json& scene, const std::string& baseDir,
                                                   const PythonPlugins& plugins, py::object log, const std::string& restartFrom,
                                                   const std::function<json(json)>& options, const std::string& name) {
  std::shared_ptr<PySimulation> self(new PySimulation());
  self->logCallback_ = std::move(log);
  PySimulation* raw = self.get();  // the sink lives inside the Simulation `raw` owns
  LogSink sink = [raw](LogLevel level, const std::string& text) {
    std::lock_guard<std::mutex> lock(raw->logMutex_);
    raw->pendingLog_.emplace_back(level, text);
  };
  const PluginRegistry registry = plugins.build(self);
  // With the GIL: `options` reads Python objects. Messages wait in the sink until released() ends.
  json consphScene;
  try {
    const bool splishsplash = isSplishSplashScene(scene);
    if (splishsplash)
      sink(LogLevel::Info, "a SPlisHSPlasH scene, run as the consph scene it maps to (docs/splishsplash.md; consph convert writes it out)");
    consphScene = splishsplash ? convertSplishSplashScene(scene, baseDir, baseDir, name, sink) : scene;
    if (options) consphScene = options(std::move(consphScene));
  } catch (...) {
    self->flushLog();
    throw;
  }
  self->released([&] {
    SceneDescription description = parseScene(consphScene, baseDir, sink);
    description.restartFrom = restartFrom;
    self->simulation_ = std::make_unique<Simulation>(std::move(description), registry, sink);
  });
  return self;
}

PySimulation::~PySimulation() = default;

Simulation& PySimulation::simulation() {
  if (busy_ && std::this_thread::get_id() != busyThread_)
    throw std::runtime_error("this Simulation is stepping in another thread; its particle data is being written: "
                             "wait for step()/run() to return");
  return *simulation_;
}

void PySimulation::requireIdle() const {
  if (busy_) throw std::runtime_error("this Simulation is stepping (in another thread, or this is called from inside one of its forces)");
}

template <class F>
void PySimulation::released(F&& f) {
  requireIdle();
  busy_ = true;
  busyThread_ = std::this_thread::get_id();
  try {
    py::gil_scoped_release nogil;
    f();
  } catch (...) {
    // The original error wins; warnings logged before it still reach Python.
    busy_ = false;
    try {
      flushLog();
      checkViews(false);
    } catch (const py::error_already_set&) {
    }
    throw;
  }
  busy_ = false;
  flushLog();
  checkViews(true);
}

void PySimulation::flushLog() {
  std::vector<std::pair<LogLevel, std::string>> pending;
  {
    std::lock_guard<std::mutex> lock(logMutex_);
    pending.swap(pendingLog_);
  }
  for (const auto& [level, text] : pending) {
    if (!logCallback_.is_none()) {
      logCallback_(level == LogLevel::Warning ? "warning" : "info", text);
    } else if (level == LogLevel::Warning) {
      const py::object category = py::module_::import("consph._consph").attr("ConsphWarning");
      if (PyErr_WarnEx(category.ptr(), text.c_str(), 1) != 0) throw py::error_already_set();
    } else {
      py::module_::import("logging").attr("getLogger")("consph").attr("info")(text);
    }
  }
}

void PySimulation::checkViews(bool raise) {
  if (!simulation_) return;
  std::string dangling, stale;
  for (FieldViewOwner* view : views_) {
    if (view->reported || view->isCurrent()) continue;
    view->reported = true;
    const FieldBase* field = simulation_->fluid().fields().find(view->field());
    std::string& list = (field && const_cast<FieldBase*>(field)->data() == view->data()) ? stale : dangling;
    if (list.find("'" + view->field() + "'") == std::string::npos) list += (list.empty() ? "'" : ", '") + view->field() + "'";
  }
  const std::string count = std::to_string(simulation_->fluid().size());
  if (!stale.empty()) {
    const std::string text = "the particle count changed to " + count + ": NumPy views of " + stale +
                             " made before show the old rows only; take fresh ones (fluid.positions etc. return a "
                             "fresh view each time; consph.is_current(view) tells)";
    const py::object category = py::module_::import("consph._consph").attr("StaleViewWarning");
    if (PyErr_WarnEx(category.ptr(), text.c_str(), 1) != 0 && raise) throw py::error_already_set();
    PyErr_Clear();
  }
  if (!dangling.empty() && raise)
    throw StaleViewError("the particle storage of " + dangling + " was reallocated (" + count +
                         " particles now) while NumPy views of it were alive: those views point to freed memory; "
                         "delete them and take fresh ones (fluid.positions etc. return a fresh view each time)");
}

void PySimulation::resizeForTesting(std::size_t n) {
  requireIdle();
  simulation_->fluid().resize(n);
  checkViews(true);
}

void PySimulation::advance(const std::function<bool()>& done, const py::object& perStep, Progress* bar) {
  const bool everyStep = !perStep.is_none();
  while (!done()) {
    released([&] {
      const Timer chunk;
      do {
        simulation_->step();
        if (bar) bar->update(double(simulation_->time()), simulation_->stepCount());
      } while (!everyStep && !done() && chunk.seconds() < 0.2);
    });
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C
    if (everyStep) perStep(shared_from_this());
  }
}

void PySimulation::step(std::size_t n) {
  const std::size_t end = simulation_->stepCount() + n;
  advance([&] { return simulation_->stepCount() >= end; }, py::none(), nullptr);
}

void PySimulation::run(double until, py::object progress) {
  const bool bar = py::isinstance<py::bool_>(progress) && progress.cast<bool>();
  if (!progress.is_none() && !py::isinstance<py::bool_>(progress) && !PyCallable_Check(progress.ptr()))
    throw py::type_error("run(progress=...): expected a bool or a callable(simulation)");
  const py::object perStep = progress.is_none() || py::isinstance<py::bool_>(progress) ? py::none() : progress;
  // Emitters' budgets cover the run until `until`; if that grew the storage, views taken before
  // point to freed memory: StaleViewError now, before any step (the next run() goes on).
  requireIdle();
  simulation_->extendRunTo(until);
  checkViews(true);
  Progress display(double(until), bar);
  advance([&] { return simulation_->reached(until); }, perStep, bar ? &display : nullptr);
  if (bar) display.finish(double(simulation_->time()), simulation_->stepCount());
}

void PySimulation::exportFrame(const std::string& path) {
  released([&] { simulation_->exportFrame(path); });
}

namespace {

// The scene as JSON with the keyword arguments of from_file / from_dict applied.
json applyOptions(json scene, const py::object& overrides, const py::object& output) {
  if (!overrides.is_none()) {
    if (!py::isinstance<py::dict>(overrides))
      throw py::type_error("overrides: expected a dict {\"dotted.key.path\": value}");
    for (auto item : overrides.cast<py::dict>()) {
      const std::string key = py::str(item.first);
      applyOverride(scene, key, toJson(item.second, key).dump());
    }
  }
  if (output.is_none()) return scene;
  if (!scene.is_object()) return scene;  // parseScene reports it
  if (py::isinstance<py::bool_>(output)) {
    scene["output"]["enabled"] = output.cast<bool>();
  } else if (py::isinstance<py::str>(output) || py::hasattr(output, "__fspath__")) {
    scene["output"]["enabled"] = true;
    scene["output"]["directory"] = py::str(py::module_::import("os").attr("fspath")(output)).cast<std::string>();
  } else {
    throw py::type_error("output: expected None (the scene's setting), False (no frames) or a directory");
  }
  return scene;
}

const PythonPlugins& pluginsArgument(const py::object& plugins) {
  // None: the process-wide registry consph.default_plugins (consph.register_force adds to it).
  const py::object registry = plugins.is_none() ? py::module_::import("consph").attr("default_plugins") : plugins;
  return registry.cast<const PythonPlugins&>();
}

std::string pathArgument(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}

}  // namespace

void bindSimulation(py::module_& m) {
  py::class_<PySimulation, std::shared_ptr<PySimulation>>(m, "Simulation", R"doc(
One SPH simulation (built from a scene file or a dict with the same JSON schema).

Build it with Simulation.from_file(path, ...) or Simulation.from_dict(scene, ...). Stepping runs
in C++ with the GIL released. Particle arrays are zero-copy NumPy views: see Fluid.
)doc")
      .def_static(
          "from_file",
          [](const py::object& path, const py::object& overrides, const py::object& plugins, py::object log,
             const py::object& output, const py::object& restart) {
            const std::string file = pathArgument(path);
            const json scene = readJsonFile(file);
            return namingSceneFile(file, [&] {
              return PySimulation::create(scene, std::filesystem::path(file).parent_path().string(), pluginsArgument(plugins),
                                          std::move(log), restart.is_none() ? std::string() : pathArgument(restart),
                                          [&](json s) { return applyOptions(std::move(s), overrides, output); },
                                          std::filesystem::path(file).stem().string());
            });
          },
          py::arg("path"), py::kw_only(), py::arg("overrides") = py::none(), py::arg("plugins") = py::none(),
          py::arg("log") = py::none(), py::arg("output") = py::none(), py::arg("restart") = py::none(),
          R"doc(Loads a JSON scene file.

overrides: {"simulation.pressureSolver.maxError": 0.01, "fluids.0.density0": 998} (the CLI's --set);
plugins: a consph.PluginRegistry (default: consph.default_plugins) whose Python forces the scene may name;
log: None (warnings -> warnings.warn(ConsphWarning), info -> logging "consph") or callable(level, message);
output: None (the scene's "output"), False (write no frames) or a directory for the frames;
restart: a checkpoint of the same scene (save_checkpoint, output.checkpointInterval) to continue from.)doc")
      .def_static(
          "from_dict",
          [](const py::object& scene, const py::object& baseDir, const py::object& overrides, const py::object& plugins,
             py::object log, const py::object& output, const py::object& restart) {
            return PySimulation::create(toJson(scene, "scene"), pathArgument(baseDir), pluginsArgument(plugins), std::move(log),
                                        restart.is_none() ? std::string() : pathArgument(restart),
                                        [&](json s) { return applyOptions(std::move(s), overrides, output); });
          },
          py::arg("scene"), py::kw_only(), py::arg("base_dir") = ".", py::arg("overrides") = py::none(),
          py::arg("plugins") = py::none(), py::arg("log") = py::none(), py::arg("output") = py::none(),
          py::arg("restart") = py::none(),
          "Builds a simulation from a dict with the scene file's schema; relative mesh paths resolve against "
          "base_dir. Keyword arguments as in from_file.")
      .def("step", &PySimulation::step, py::arg("n") = 1,
           "Advances n time steps (GIL released; Ctrl-C is honoured between steps).")
      .def(
          "run",
          [](PySimulation& s, const py::object& until, py::object progress) {
            const double end = until.is_none() ? double(s.simulation().scene().stopAt) : until.cast<double>();
            // NaN would never be reached and inf never ends: the CLI's --stop-at refuses both too.
            if (!std::isfinite(end)) throw py::value_error("run: until must be a finite time, got " + std::to_string(end));
            s.run(end, std::move(progress));
          },
          py::arg("until") = py::none(), py::arg("progress") = false,
          "Steps until simulated time `until` (default: the scene's simulation.stopAt). progress: True draws a "
          "progress bar on stderr; a callable(sim) is called after every step.")
      .def_property_readonly("time", [](PySimulation& s) { return s.simulation().time(); }, "simulated time, s")
      .def_property_readonly("dt", [](PySimulation& s) { return s.simulation().dt(); },
                             "the last step's time step, s (the initial one before the first step)")
      .def_property_readonly("step_count", [](PySimulation& s) { return s.simulation().stepCount(); })
      .def_property_readonly("particle_radius", [](PySimulation& s) { return s.simulation().scene().particleRadius; })
      .def_property_readonly("scene", [](PySimulation& s) { return toPython(s.simulation().scene().raw); },
                             "the scene as a dict (after overrides)")
      .def("summary", [](PySimulation& s) { return toPython(s.simulation().summary()); },
           "The run's summary figures as a dict (the CLI's --summary-json).")
      .def_property_readonly(
          "probes",
          [](PySimulation& s) {
            const Probes* p = s.simulation().probes();
            return toPython(p ? p->latest() : json::object());
          },
          "The scene's probes after the last step, {column: value} as in probes.csv (pressure in Pa, level in m, "
          "force probes as NAME.fx .. NAME.tz in N and N m); empty without probes.")
      .def_property_readonly(
          "bodies",
          [](PySimulation& s) {
            // Copies: a scene has a handful of bodies, and their state lives in Eigen types.
            py::list out;
            const MovingBodies* system = s.simulation().movingBodies();
            if (!system) return out;
            auto vec = [](const Vector3r& v) { return py::make_tuple(v[0], v[1], v[2]); };
            for (std::size_t i = 0; i < system->count(); ++i) {
              const MovingBodyState b = system->state(i);
              py::dict d;
              d["name"] = b.name;
              d["motion"] = b.motion == BodyMotion::Dynamic ? "dynamic" : "animated";
              d["mass"] = b.mass;
              d["position"] = vec(b.x);
              d["orientation"] = py::make_tuple(b.q.w(), b.q.x(), b.q.y(), b.q.z());
              d["velocity"] = vec(b.v);
              d["angular_velocity"] = vec(b.w);
              d["fluid_force"] = vec(b.fluidForce);
              d["fluid_torque"] = vec(b.fluidTorque);
              out.append(d);
            }
            return out;
          },
          "The moving bodies' state as a list of dicts in scene order (copies; the columns of "
          "bodies.csv): name, motion, mass (kg), position of the centre of mass (m), orientation "
          "quaternion (w, x, y, z), velocity, angular_velocity, and the fluid's force and torque over "
          "the last step (N, N m about the centre of mass).")
      .def(
          "fluid",
          [](const std::shared_ptr<PySimulation>& s, const py::object& name) {
            const std::string& actual = s->simulation().fluid().name();
            if (!name.is_none() && name.cast<std::string>() != actual)
              throw py::key_error("no fluid '" + name.cast<std::string>() + "'; fluids: " + actual);
            return PyFluid{s};
          },
          py::arg("name") = py::none(), "The fluid called `name` (default: the only one).")
      .def_property_readonly("fluids",
                             [](const std::shared_ptr<PySimulation>& s) { return py::make_tuple(PyFluid{s}); })
      .def("export_frame", [](PySimulation& s, const py::object& path) { s.exportFrame(pathArgument(path)); },
           py::arg("path"),
           "Writes the current particles to one frame file, in the format its extension names (.vtu, .ply, .bgeo, "
           ".bgeo.gz), with the scene's output.attributes at the build's precision (.bgeo: float32).")
      .def("save_checkpoint", [](PySimulation& s, const py::object& path) { s.simulation().saveCheckpoint(pathArgument(path)); },
           py::arg("path"),
           "Writes the whole state (particle fields, bodies, emitters, time, step count, time-step state) to a "
           "checkpoint file; Simulation.from_file/from_dict(..., restart=path) continues from it bit for bit.")
      .def_property(
          "output_directory", [](PySimulation& s) { return s.simulation().scene().output.directory; },
          [](PySimulation& s, const py::object& dir) {
            s.requireIdle();
            s.simulation().setOutputDirectory(pathArgument(dir));
          },
          "folder of the frame series (setting it enables output)")
      .def_property(
          "output_enabled", [](PySimulation& s) { return s.simulation().scene().output.enabled; },
          [](PySimulation& s, bool on) {
            s.requireIdle();
            s.simulation().setOutputEnabled(on);
          },
          "whether frames are written at output_fps")
      .def_property(
          "output_fps", [](PySimulation& s) { return s.simulation().scene().output.fps; },
          [](PySimulation& s, Real fps) {
            s.requireIdle();
            if (!(fps > 0) || !std::isfinite(fps)) throw py::value_error("output_fps: must be finite and > 0");
            s.simulation().setOutputFps(fps);
          })
      .def("__repr__", [](PySimulation& s) {
        Simulation& sim = s.simulation();
        return "<consph.Simulation '" + sim.scene().raw.value("name", std::string()) + "': " +
               std::to_string(sim.fluid().size()) + " fluid particles, t = " + std::to_string(sim.time()) + " s, " +
               std::to_string(sim.stepCount()) + " steps>";
      });

  m.def("set_num_threads", [](long long n) {
    if (n < 1) throw py::value_error("set_num_threads: expected n >= 1");
    std::string warning;
    omp_set_num_threads(clampThreadCount(n, warning));
    if (!warning.empty() &&
        PyErr_WarnEx(py::module_::import("consph._consph").attr("ConsphWarning").ptr(), ("set_num_threads: " + warning).c_str(), 1) < 0)
      throw py::error_already_set();  // warnings-as-errors
  }, py::arg("n"), "OpenMP threads used by steps started from this Python thread (at most 4x the hardware threads, 1024).");
  m.def("get_num_threads", [] { return omp_get_max_threads(); });
}

}  // namespace consph::python
