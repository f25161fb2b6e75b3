// libFuzzer target for the scene reader (issue 16): a JSON text goes through what the CLI does
// with a scene file (the limits check, the parser, parseScene) and may only end in a scene or
// an InputError. Anything else is a finding: a crash or sanitizer report (built with
// -fsanitize=fuzzer,address,undefined), or an exception of another type (the CLI's
// "internal error", exit 4), turned into an abort so that libFuzzer keeps the input.
//
// Built by bench/fuzz_scene.sh (clang only; never part of the default build or CI), or with
// cmake -DCONSPH_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "Simulation/JsonLimits.h"
#include "Simulation/Scene.h"
#include "Utilities/Error.h"

#ifndef CONSPH_FUZZ_SCENE_DIR
#define CONSPH_FUZZ_SCENE_DIR "data/scenes"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  consph::json scene;
  try {
    consph::checkJsonLimits(text, "fuzz");
    scene = consph::json::parse(text);  // malformed JSON: readJsonFile's InputError
  } catch (const consph::InputError&) {
    return 0;
  } catch (const consph::json::parse_error&) {
    return 0;
  }
  try {
    // Mesh paths resolve against the bundled scenes' folder, as for the seeds.
    (void)consph::parseScene(scene, CONSPH_FUZZ_SCENE_DIR, {});
  } catch (const consph::InputError&) {
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scene_parser_fuzzer: not an InputError: %s\n", e.what());
    std::abort();
  }
  return 0;
}
