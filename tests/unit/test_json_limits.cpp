// JSON limits checked on the text before parsing: nesting depth and numbers a double can hold,
// reported with file, line and column (issue 16: 1e5-deep values overflowed the stack, 1e999
// escaped as an internal error without a position).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "Simulation/JsonLimits.h"
#include "Simulation/Scene.h"
#include "Utilities/Error.h"

using namespace consph;

namespace {
std::string writeTemp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path.string();
}

std::string readError(const std::string& path) {
  try {
    readJsonFile(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string nested(int depth) { return std::string(std::size_t(depth), '[') + std::string(std::size_t(depth), ']'); }
}  // namespace

TEST(SceneJsonLimits, NestingAtTheLimitParses) {
  const std::string path = writeTemp("consph_depth_ok.json", "{\"description\": " + nested(kMaxJsonDepth - 1) + "}");
  EXPECT_NO_THROW(readJsonFile(path));
}

TEST(SceneJsonLimits, NestingPastTheLimitNamesLineAndColumn) {
  // The top-level object is level 1, so the array opening at column 17 is level 2, ...
  const std::string path = writeTemp("consph_depth_bad.json", "{\n\"description\": " + nested(kMaxJsonDepth) + "}");
  const std::string e = readError(path);
  EXPECT_NE(e.find(path + ":2:" + std::to_string(15 + kMaxJsonDepth) + ": JSON nested deeper than 200 levels"), std::string::npos) << e;
}

TEST(SceneJsonLimits, HundredThousandLevelsIsAnErrorNotACrash) {
  const std::string path = writeTemp("consph_depth_huge.json", "{\"description\": " + nested(100000) + "}");
  EXPECT_NE(readError(path).find("nested deeper than"), std::string::npos);
}

TEST(SceneJsonLimits, BracketsInsideStringsDoNotCount) {
  const std::string path =
      writeTemp("consph_depth_string.json", "{\"description\": \"" + nested(1000) + " \\\" [[[\", \"name\": \"x\"}");
  EXPECT_NO_THROW(readJsonFile(path));
}

TEST(SceneJsonLimits, NumberOutOfDoubleRangeNamesLineAndColumn) {
  const std::string path = writeTemp("consph_overflow.json", "{\"simulation\": {\n  \"stopAt\": 1e999}}");
  EXPECT_NE(readError(path).find(path + ":2:13: number 1e999 is out of the range of a double"), std::string::npos)
      << readError(path);
  EXPECT_NE(readError(writeTemp("consph_overflow2.json", "[-2e400]")).find(":1:2: number -2e400"), std::string::npos);
  EXPECT_NO_THROW(readJsonFile(writeTemp("consph_big_ok.json", "[1e308, -1e-400, 123456789012345678901234567890]")));
}

TEST(SceneJsonLimits, OverrideValuesAreChecked) {
  json scene = json::object();
  try {
    applyOverride(scene, "simulation.stopAt", "1e999");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--set simulation.stopAt:1:1: number 1e999"), std::string::npos) << e.what();
  }
  EXPECT_THROW(applyOverride(scene, "description", nested(50000)), InputError);
  EXPECT_NO_THROW(applyOverride(scene, "description", "[[1]]"));
}
