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

}  // namespace consph
