// Exceptions: the library never exits; the CLI and the Python module turn these into a one-line
// message and a non-zero exit code or a Python exception.
#pragma once
#include <stdexcept>
#include <string>

namespace consph {

// Bad input: scene file, parameter, mesh file. The message names the JSON path or file.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The simulation blew up: NaN, particles leaving the domain, solver cap hit every step.
struct SimulationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Output could not be written: a full disk, a missing permission, a folder that is a file. Not
// the input's fault, so it has its own exit code (5).
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace consph
