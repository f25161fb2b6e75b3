// Errors about a scene file's contents name the file.
#pragma once
#include <string>

#include "Utilities/Error.h"

namespace consph {

// Runs `build` (parsing the scene read from the file `path`, or building a simulation from it)
// and names the file in the InputError it throws: an error about the scene's contents reads
// "FILE: JSON.PATH: why". A message that starts with the file already is left as it is.
template <class Build>
auto namingSceneFile(const std::string& path, Build&& build) -> decltype(build()) {
  try {
    return build();
  } catch (const InputError& e) {
    if (std::string(e.what()).rfind(path, 0) == 0) throw;
    throw InputError(path + ": " + e.what());
  }
}

}  // namespace consph
