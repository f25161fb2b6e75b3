// The consph command line: run a scene, list plugins.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "Simulation/SceneFile.h"
#include "Simulation/Simulation.h"
#include "Simulation/SplishSplashScene.h"
#include "Utilities/Error.h"
#include "Utilities/Progress.h"
#include "Utilities/ThreadCount.h"
#include "Utilities/VtkWriter.h"

using namespace consph;

namespace {

const char* kUsage =
    "usage: consph [run] [SCENE] [options]       run SCENE (default: data/scenes/DamBreak.json)\n"
    "       consph --list-plugins [--json]      list every plugin with its parameters\n"
    "       consph convert IN.json OUT.json     write the consph scene a SPlisHSPlasH scene maps to (docs/splishsplash.md)\n"
    "                                           (consph runs a SPlisHSPlasH scene as it is, too)\n"
    "options:\n"
    "  --stop-at T            simulated end time in seconds (default: the scene's simulation.stopAt)\n"
    "  --output-dir D         write frames to D (default: the scene's output.directory)\n"
    "  --fps N                frames per simulated second\n"
    "  --no-output            write no frames\n"
    "  --overwrite            clear another run's frames from the output folder (default: refuse such a folder)\n"
    "  --threads N            OpenMP threads (default: all cores; at most 4x the hardware threads, 1024)\n"
    "  --max-particles N      refuse scenes estimated above N fluid particles' memory (default: half this machine's memory,\n"
    "                         2 KB per particle; the scene key simulation.maxParticles)\n"
    "  --set KEY.PATH=VALUE   override a scene value, e.g. --set simulation.pressureSolver.maxError=0.01\n"
    "  --summary-json FILE    write the run's summary as JSON (-: standard output, the table then goes to stderr)\n"
    "  --restart FILE         continue from a checkpoint (output.checkpointInterval) of the same scene\n"
    "  --quiet                no progress, no summary table (warnings and errors still show)\n";

std::string defaultScene() {
  for (const std::string& candidate : {std::string("data/scenes/DamBreak.json"), std::string(CONSPH_SOURCE_DIR) + "/data/scenes/DamBreak.json"})
    if (std::filesystem::exists(candidate)) return candidate;
  return "data/scenes/DamBreak.json";
}

void printSummary(const json& s, FILE* out) {
  const auto& p = s["phaseSeconds"];
  std::fprintf(out, "\nsummary\n");
  std::fprintf(out, "  fluid particles           %zu\n", s["fluidParticles"].get<std::size_t>());
  std::fprintf(out, "  boundary particles        %zu\n", s["boundaryParticles"].get<std::size_t>());
  std::fprintf(out, "  steps                     %zu\n", s["steps"].get<std::size_t>());
  std::fprintf(out, "  simulated time            %.4f s\n", s["simulatedTime"].get<double>());
  std::fprintf(out, "  wall time                 %.2f s (%.2f ms/step, %.3f us/particle-step)\n", s["wallSeconds"].get<double>(),
              s["msPerStep"].get<double>(), s["usPerParticleStep"].get<double>());
  std::fprintf(out, "  threads, precision        %d, %s\n", s["threads"].get<int>(), s["precision"].get<std::string>().c_str());
  std::fprintf(out, "  solver, boundary pressure %s, %s\n", s["pressureSolver"].get<std::string>().c_str(),
              s["boundaryPressure"].get<std::string>().c_str());
  std::fprintf(out, "  iterations per step       %.2f pressure, %.2f divergence\n", s["averagePressureIterations"].get<double>(),
              s["averageDivergenceIterations"].get<double>());
  std::fprintf(out, "  density error             %.4f %% average, %.4f %% max\n", s["averageDensityErrorPercent"].get<double>(),
              s["maxDensityErrorPercent"].get<double>());
  std::fprintf(out, "  particles lost            %zu\n", s["particlesLost"].get<std::size_t>());
  std::fprintf(out, "  seconds per phase         neighbours %.2f, densities %.2f, divergence %.2f, forces %.2f, pressure %.2f, "
              "integration %.2f, export %.2f\n",
              p["neighbourSearch"].get<double>(), p["densities"].get<double>(), p["divergenceSolve"].get<double>(),
              p["nonPressureForces"].get<double>(), p["pressureSolve"].get<double>(), p["integration"].get<double>(),
              p["export"].get<double>());
}

// The signal that asked the run to stop (SIGINT, SIGTERM), 0 while none did: the CLI's one
// global, as a signal handler can reach nothing else. A second signal gets the default action,
// so a run that does not stop can still be killed.
volatile std::sig_atomic_t g_signal = 0;

void onSignal(int signal) {
  g_signal = signal;
  std::signal(signal, SIG_DFL);
}

struct Options {
  std::string scene;
  double stopAt = -1, fps = -1, maxParticles = -1;
  std::string outputDir, summaryJson, restart;
  bool noOutput = false, overwrite = false, quiet = false, listPlugins = false, listJson = false;
  long long threads = 0;
  std::vector<std::pair<std::string, std::string>> overrides;
};

Options parseArgs(int argc, char** argv) {
  Options o;
  auto need = [&](int& i, const char* flag) -> std::string {
    if (i + 1 >= argc) throw InputError(std::string(flag) + ": missing value");
    return argv[++i];
  };
  auto number = [](const std::string& flag, const std::string& v) {
    try {
      std::size_t used = 0;
      const double x = std::stod(v, &used);
      // stod reads "nan" and "inf": neither is a time, a rate or a count.
      if (used != v.size() || !std::isfinite(x)) throw std::invalid_argument(v);
      return x;
    } catch (...) {
      throw InputError(flag + ": expected a finite number, got '" + v + "'");
    }
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "run" && i == 1) continue;
    if (a == "--help" || a == "-h") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (a == "--version") {
      std::printf("consph %s (%s)\n", CONSPH_VERSION, precisionName());
      std::exit(0);
    } else if (a == "--list-plugins") o.listPlugins = true;
    else if (a == "--json") o.listJson = true;
    else if (a == "--stop-at") {
      o.stopAt = number(a, need(i, "--stop-at"));
      // The scene's simulation.stopAt range.
      if (o.stopAt < 0 || o.stopAt > 1e9) throw InputError("--stop-at: must be in [0, 1e9] s");
    } else if (a == "--output-dir") o.outputDir = need(i, "--output-dir");
    else if (a == "--fps") {
      o.fps = number(a, need(i, "--fps"));
      if (o.fps <= 0) throw InputError("--fps: must be > 0");
    } else if (a == "--threads") {
      const double t = number(a, need(i, "--threads"));
      if (t < 1 || t != std::floor(t)) throw InputError("--threads: expected a positive integer");
      o.threads = (long long)std::min(t, 1e12);
    } else if (a == "--max-particles") {
      o.maxParticles = number(a, need(i, "--max-particles"));
      if (o.maxParticles < 1) throw InputError("--max-particles: must be >= 1");
    } else if (a == "--set") {
      const std::string kv = need(i, "--set");
      const auto eq = kv.find('=');
      if (eq == std::string::npos || eq == 0) throw InputError("--set: expected KEY.PATH=VALUE, got '" + kv + "'");
      o.overrides.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
    } else if (a == "--summary-json") o.summaryJson = need(i, "--summary-json");
    else if (a == "--restart") o.restart = need(i, "--restart");
    else if (a == "--no-output") o.noOutput = true;
    else if (a == "--overwrite") o.overwrite = true;
    else if (a == "--quiet") o.quiet = true;
    else if (!a.empty() && a[0] == '-') throw InputError("unknown option '" + a + "' (see consph --help)");
    else if (o.scene.empty()) o.scene = a;
    else throw InputError("unexpected argument '" + a + "' (one scene at a time)");
  }
  return o;
}

// `consph convert IN OUT`: the consph scene equivalent to the SPlisHSPlasH scene IN, checked by
// parsing it as consph would run it, then written to OUT with file names relative to OUT's folder.
int convertScene(int argc, char** argv) {
  if (argc != 4) throw InputError("convert: expected consph convert IN.json OUT.json");
  const std::filesystem::path in(argv[2]), out(argv[3]);
  const json scene = readJsonFile(in.string());
  if (!isSplishSplashScene(scene))
    throw InputError(in.string() + ": not a SPlisHSPlasH scene (it has none of Configuration, Materials, FluidBlocks, FluidModels, "
                     "RigidBodies, Emitters, AnimationFields, or it has consph's \"fluids\")");
  int warnings = 0;
  const LogSink stderrLog = stderrLogSink(false);
  const LogSink log = [&](LogLevel level, const std::string& text) {
    warnings += level == LogLevel::Warning;
    stderrLog(level, text);
  };
  json converted;
  try {
    converted = convertSplishSplashScene(scene, in.parent_path().string(), out.parent_path().string(), in.stem().string(), log);
    parseScene(converted, out.parent_path().string(), [](LogLevel, const std::string&) {});
  } catch (const InputError& e) {
    throw InputError(in.string() + ": " + e.what());
  }
  writeFileAtomically(out.string(), converted.dump(2) + "\n");
  std::fprintf(stderr, "consph: wrote %s (%d warning%s above)\n", out.string().c_str(), warnings, warnings == 1 ? "" : "s");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc > 1 && std::string(argv[1]) == "convert") return convertScene(argc, argv);
    Options o = parseArgs(argc, argv);
    if (o.listPlugins) {
      if (o.listJson) std::printf("%s\n", builtinPlugins().toJson().dump(2).c_str());
      else std::fputs(builtinPlugins().describe().c_str(), stdout);
      return 0;
    }
    if (o.threads > 0) {
      std::string warning;
      omp_set_num_threads(clampThreadCount(o.threads, warning));
      if (!warning.empty()) std::fprintf(stderr, "consph: warning: --threads: %s\n", warning.c_str());
    }
    if (o.scene.empty()) o.scene = defaultScene();
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    LogSink log = stderrLogSink(o.quiet);
    // Output options are scene overrides, so the simulation never touches the scene's own
    // output folder when another one (or none) is asked for.
    if (o.noOutput) o.overrides.emplace_back("output.enabled", "false");
    if (o.overwrite) o.overrides.emplace_back("output.overwrite", "true");
    if (!o.outputDir.empty()) o.overrides.emplace_back("output.directory", json(o.outputDir).dump());
    if (o.fps > 0) o.overrides.emplace_back("output.fps", json(o.fps).dump());
    if (o.maxParticles > 0) o.overrides.emplace_back("simulation.maxParticles", json(o.maxParticles).dump());
    SceneDescription scene = loadSceneFile(o.scene, o.overrides, log);
    scene.restartFrom = o.restart;
    auto sim = namingSceneFile(o.scene, [&] { return std::make_unique<Simulation>(std::move(scene), builtinPlugins(), log); });

    const double stopAt = o.stopAt >= 0 ? o.stopAt : double(sim->scene().stopAt);
    if (!o.quiet)
      std::fprintf(stderr, "consph: %s, %zu fluid + %zu boundary particles, %s, %d threads, %s -> %s\n", o.scene.c_str(),
                   sim->fluid().size(), sim->boundary().size(), precisionName(), omp_get_max_threads(),
                   sim->scene().pressureSolver["type"].get<std::string>().c_str(),
                   sim->scene().output.enabled ? sim->scene().output.directory.c_str() : "(no output)");
    Progress progress(stopAt, !o.quiet);
    // Every run ends with a record: a blow-up (3), a failed write (5) or a signal (128 + n) stops
    // the loop at the end of a step, and the summary is still printed and written.
    int status = 0;
    std::string state = "ok", failure;
    try {
      sim->run(
          stopAt, [&](const Simulation& s) { progress.update(s.time(), s.stepCount()); },
          [] { return g_signal != 0; });
      if (g_signal != 0) {
        status = 128 + g_signal;
        state = "interrupted";
        failure = std::string("interrupted by ") + (g_signal == SIGINT ? "SIGINT" : "SIGTERM") + " at step " +
                  std::to_string(sim->stepCount()) + ", t = " + std::to_string(double(sim->time())) + " s";
      }
    } catch (const SimulationError& e) {
      failure = e.what();
      status = 3;
      state = "failed";
    } catch (const OutputError& e) {
      failure = e.what();
      status = 5;
      state = "output failed";
    }
    progress.finish(sim->time(), sim->stepCount());
    json summary = sim->summary();
    summary["scene"] = o.scene;
    summary["status"] = state;
    if (!failure.empty()) summary["error"] = failure;
    const bool jsonToStdout = o.summaryJson == "-";
    if (!o.summaryJson.empty()) {
      try {
        if (jsonToStdout) std::printf("%s\n", summary.dump(2).c_str());
        else writeFileAtomically(o.summaryJson, summary.dump(2) + "\n");
      } catch (const OutputError& e) {
        std::fprintf(stderr, "consph: error: --summary-json: %s\n", e.what());
        if (status == 0) status = 5;
      }
    }
    // With the JSON on standard output the table goes to standard error.
    if (!o.quiet) printSummary(summary, jsonToStdout ? stderr : stdout);
    if (!failure.empty()) std::fprintf(stderr, "consph: error: %s (frames written so far are kept)\n", failure.c_str());
    return status;
  } catch (const InputError& e) {
    std::fprintf(stderr, "consph: error: %s\n", e.what());
    return 2;
  } catch (const SimulationError& e) {
    std::fprintf(stderr, "consph: error: %s\n", e.what());
    return 3;
  } catch (const OutputError& e) {
    std::fprintf(stderr, "consph: error: %s\n", e.what());
    return 5;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consph: internal error: %s\n", e.what());
    return 4;
  }
}
