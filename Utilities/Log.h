// Minimal logging: warnings and info go to stderr, and can be captured (tests, Python).
#pragma once
#include <functional>
#include <string>

namespace consph {

enum class LogLevel { Info, Warning };

// A sink per Simulation (no global logger): whoever owns the simulation decides where text goes.
using LogSink = std::function<void(LogLevel, const std::string&)>;

LogSink stderrLogSink(bool quiet);

}  // namespace consph
