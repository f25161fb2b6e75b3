// Every run ends with a record (issue 16): a signal stops the run at the end of a step with the
// summary (status "interrupted", exit 130 / 143); a failed write exits 5 with the summary and
// leaves no .tmp; "-" is standard output; a FIFO or a symlink is written through, never renamed
// over; a fluid name cannot leave the output folder or break the .pvd.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>

#include "CliUtil.h"
#include "TestUtil.h"
#include "Utilities/OutputFolder.h"
#include "Utilities/VtkWriter.h"

using namespace consph;
using consph::test::runCommand;
using consph::test::tempDir;

namespace {
std::string writeScene(const std::string& dir, const json& scene) {
  std::ofstream(dir + "/scene.json") << scene.dump();
  return dir + "/scene.json";
}
const std::string kCli = CONSPH_BINARY;
}  // namespace

TEST(RunRecordFailures, SummaryJsonDashIsStandardOutput) {
  const std::string dir = tempDir("consph_record_dash");
  const std::string scene = writeScene(dir, test::tinyTankScene(0.01));
  // stdout only (stderr dropped): it must be the JSON alone.
  FILE* pipe = popen(("cd " + dir + " && " + kCli + " " + scene + " --no-output --summary-json - 2>/dev/null").c_str(), "r");
  std::string out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof(buffer), pipe)) out += buffer;
  ASSERT_EQ(pclose(pipe), 0);
  EXPECT_EQ(json::parse(out)["status"], "ok") << out;
  EXPECT_FALSE(std::filesystem::exists(dir + "/-"));
}

// The case: /dev/stdout (a symlink to the process's fd 1, here a pipe) is written
// through, never renamed over (as root, the rename replaced the machine's /dev/stdout).
TEST(RunRecordFailures, SummaryJsonToDevStdoutWritesThroughTheLink) {
  const std::string dir = tempDir("consph_record_devstdout");
  const std::string scene = writeScene(dir, test::tinyTankScene(0.01));
  const bool wasLink = std::filesystem::is_symlink("/dev/stdout");
  FILE* pipe = popen(("cd " + dir + " && " + kCli + " " + scene + " --no-output --summary-json /dev/stdout 2>/dev/null").c_str(), "r");
  std::string out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof(buffer), pipe)) out += buffer;
  ASSERT_EQ(pclose(pipe), 0);
  // The JSON, then the text summary (stdout is not "-" here, so the CLI prints it too).
  const std::size_t end = out.find("\n}");
  ASSERT_NE(end, std::string::npos) << out;
  EXPECT_EQ(json::parse(out.substr(0, end + 2))["status"], "ok") << out;
  EXPECT_EQ(std::filesystem::is_symlink("/dev/stdout"), wasLink);
  EXPECT_FALSE(std::filesystem::is_regular_file(std::filesystem::symlink_status("/dev/stdout")));
}

TEST(RunRecordFailures, FifoAndSymlinkTargetsAreWrittenThrough) {
  const std::string dir = tempDir("consph_record_fifo");
  ASSERT_EQ(mkfifo((dir + "/pipe").c_str(), 0600), 0);
  const std::string scene = writeScene(dir, test::tinyTankScene(0.01));
  const auto r = runCommand("cat " + dir + "/pipe > " + dir + "/read.json & " + kCli + " " + scene +
                            " --quiet --no-output --summary-json " + dir + "/pipe; rc=$?; wait; exit $rc");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(std::filesystem::is_fifo(dir + "/pipe"));  // not replaced by a regular file
  EXPECT_EQ(readJsonFile(dir + "/read.json")["status"], "ok");
  std::ofstream(dir + "/target.json") << "{}";
  std::filesystem::create_symlink(dir + "/target.json", dir + "/link.json");
  writeFileAtomically(dir + "/link.json", "{\"a\": 1}");
  EXPECT_TRUE(std::filesystem::is_symlink(dir + "/link.json"));
  EXPECT_EQ(readJsonFile(dir + "/target.json")["a"], 1);
}

TEST(RunRecordFailures, FailedWriteThrowsOutputErrorAndLeavesNoTemporary) {
  const std::string dir = tempDir("consph_record_full");
  EXPECT_THROW(writeFileAtomically("/dev/full", "x"), OutputError);  // a device: written in place, ENOSPC
  // The temporary itself on a full disk: its name is a link to /dev/full.
  std::filesystem::create_symlink("/dev/full", dir + "/frame.vtu.tmp");
  EXPECT_THROW(writeFileAtomically(dir + "/frame.vtu", "x"), OutputError);
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(dir + "/frame.vtu.tmp")));
  EXPECT_FALSE(std::filesystem::exists(dir + "/frame.vtu"));
}

TEST(RunRecordFailures, FullDiskExitsFiveWithTheSummary) {
  const std::string dir = tempDir("consph_record_disk");
  const std::string scene = writeScene(dir, test::tinyTankScene(0.05));
  std::filesystem::create_directories(dir + "/out");
  std::filesystem::create_symlink("/dev/full", dir + "/out/water_00001.vtu.tmp");  // the second frame hits a full disk
  auto r = runCommand(kCli + " " + scene + " --quiet --fps 100 --output-dir " + dir + "/out --summary-json " + dir + "/s.json");
  EXPECT_EQ(r.status, 5) << r.output;
  EXPECT_NE(r.output.find("cannot write '" + dir + "/out/water_00001.vtu.tmp'"), std::string::npos) << r.output;
  const json s = readJsonFile(dir + "/s.json");
  EXPECT_EQ(s["status"], "output failed");
  EXPECT_GT(s["steps"].get<int>(), 0);
  for (auto& e : std::filesystem::directory_iterator(dir + "/out")) EXPECT_NE(e.path().extension(), ".tmp") << e.path();
  // The summary file itself on a full disk: exit 5 after the run, the table still printed.
  r = runCommand(kCli + " " + scene + " --no-output --summary-json /dev/full");
  EXPECT_EQ(r.status, 5) << r.output;
  EXPECT_NE(r.output.find("--summary-json: cannot write '/dev/full'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("summary"), std::string::npos) << r.output;
}

TEST(RunRecordFailures, SignalsStopAtAStepWithTheSummary) {
  const std::string dir = tempDir("consph_record_signal");
  json scene = test::tinyTankScene(1000);
  scene["simulation"]["maxTimeStep"] = 1e-4;  // long enough to still run when the signal comes
  const std::string path = writeScene(dir, scene);
  for (const auto& [name, code] : {std::pair<std::string, int>{"INT", 130}, {"TERM", 143}}) {
    const std::string summary = dir + "/" + name + ".json";
    const auto r = runCommand("{ " + kCli + " " + path + " --quiet --no-output --threads 1 --summary-json " + summary +
                              " & pid=$!; sleep 1; kill -" + name + " $pid; wait $pid; }");
    EXPECT_EQ(r.status, code) << r.output;
    EXPECT_NE(r.output.find("interrupted by SIG" + name + " at step "), std::string::npos) << r.output;
    const json s = readJsonFile(summary);
    EXPECT_EQ(s["status"], "interrupted");
    EXPECT_GT(s["steps"].get<int>(), 0);
  }
}

TEST(RunRecordFailures, FluidNamesCannotLeaveTheOutputFolder) {
  const std::string dir = tempDir("consph_record_names");
  const std::string scene = writeScene(dir, test::tinyTankScene(0.01));
  for (const auto& [value, message] : std::vector<std::pair<std::string, std::string>>{
           {"../x", "fluids[0].name: '../x' must not contain '/'"},
           {"a/b", "must not contain '/'"},
           {"\"\"", "fluids[0].name: must not be empty"},
           {".hidden", "start with '.'"},
           {"\"a<b\"", "written into the .pvd's XML"},
           {"\"\\u0007\"", "fluids[0].name: must be printable UTF-8"}}) {
    const auto r = runCommand(kCli + " " + scene + " --quiet --output-dir " + dir + "/out --set 'fluids.0.name=" + value + "'");
    EXPECT_EQ(r.status, 2) << value << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << value << ": " << r.output;
  }
  // A 0xff byte (not UTF-8) straight from the file.
  std::string text = test::tinyTankScene(0.01).dump();
  text.replace(text.find("\"water\""), 7, "\"wa\xffter\"");
  std::ofstream(dir + "/bad.json") << text;
  const auto r = runCommand(kCli + " " + dir + "/bad.json --quiet --no-output");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x"));
}

TEST(RunRecordFailures, OutputFolderOfAnotherRunIsRefusedUnlessOverwrite) {
  const std::string dir = tempDir("consph_record_owned");
  const std::string scene = writeScene(dir, test::tinyTankScene(0.2));
  const std::string run = kCli + " " + scene + " --quiet --output-dir " + dir + "/out --fps 50";
  ASSERT_EQ(runCommand(run).status, 0);
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/water_00010.vtu"));
  std::ofstream(dir + "/out/notes.txt") << "mine";
  // A second run into the folder: refused, nothing touched.
  auto r = runCommand(run + " --stop-at 0.05");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("output folder '" + dir + "/out' holds another run's files (boundary.vtu and "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("pass --overwrite"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/water_00010.vtu"));
  // --overwrite clears consph's files only: no stale frame beside the shorter series.
  r = runCommand(run + " --stop-at 0.05 --overwrite --set fluids.0.density0=998");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out/water_00010.vtu"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/water_00002.vtu"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/notes.txt"));
  // The resolved scene (after --set) beside the frames.
  EXPECT_EQ(readJsonFile(dir + "/out/scene.resolved.json")["fluids"][0]["density0"], 998);
}

TEST(RunRecordFailures, RunFilesAreRecognised) {
  for (const char* f : {"water_00000.vtu", "water.pvd", "boundary.vtu", "bodies.csv", "bodies_00012.vtu", "scene.resolved.json",
                        "water_00003.vtu.tmp"})
    EXPECT_TRUE(isRunFile(f)) << f;
  for (const char* f : {"notes.txt", "water_1.vtu", "summary.json", "mesh.vtu"}) EXPECT_FALSE(isRunFile(f)) << f;
}
