// The output folder is owned: a run writes its frames only into a folder that holds no other
// run's files, or clears those first when asked (--overwrite, output.overwrite). Re-running
// into a folder otherwise left the old run's extra frames beside a shorter .pvd.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace consph {

// Files consph writes into an output folder: NAME_NNNNN.vtu / .ply / .bgeo / .bgeo.gz frames,
// NAME.pvd series, boundary.vtu, bodies.csv, probes.csv, scene.resolved.json,
// checkpoint_NNNNN.state, and the .tmp of any of them.
bool isRunFile(const std::string& fileName);

// The run files directly in `directory` (none when it does not exist), sorted: regular files
// only, as consph writes nothing else (a link to a device or a folder is not a run's output).
std::vector<std::filesystem::path> runFilesIn(const std::string& directory);

// Creates `directory` if needed. When it holds run files: removes them if `overwrite`, else
// throws InputError naming the folder, a file and how many (consph's own files only are
// touched; anything else in the folder stays). Failing file operations throw OutputError.
void claimOutputFolder(const std::string& directory, bool overwrite);

}  // namespace consph
