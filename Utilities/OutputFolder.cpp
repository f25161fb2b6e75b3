#include "Utilities/OutputFolder.h"

#include <algorithm>
#include <regex>

#include "Utilities/Error.h"

namespace consph {

bool isRunFile(const std::string& fileName) {
  static const std::regex pattern(R"((.+_[0-9]{5}\.(vtu|ply|bgeo|bgeo\.gz)|.+\.pvd|boundary\.vtu|bodies\.csv|probes\.csv|scene\.resolved\.json|checkpoint_[0-9]{5}\.state)(\.tmp)?)");
  return std::regex_match(fileName, pattern);
}

std::vector<std::filesystem::path> runFilesIn(const std::string& directory) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::is_directory(directory, ec)) return files;
  for (const fs::directory_entry& e : fs::directory_iterator(directory, ec))
    if (e.is_regular_file(ec) && isRunFile(e.path().filename().string())) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

void claimOutputFolder(const std::string& directory, bool overwrite) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec || !fs::is_directory(directory)) throw OutputError("cannot create output folder '" + directory + "'" + (ec ? ": " + ec.message() : ""));
  const std::vector<fs::path> files = runFilesIn(directory);
  if (files.empty()) return;
  if (!overwrite)
    throw InputError("output folder '" + directory + "' holds another run's files (" + files.front().filename().string() +
                     (files.size() > 1 ? " and " + std::to_string(files.size() - 1) + " more" : std::string()) +
                     "); pass --overwrite (output.overwrite) to clear them, or choose another folder");
  for (const fs::path& f : files)
    if (!fs::remove(f, ec) && ec) throw OutputError("cannot remove '" + f.string() + "': " + ec.message());
}

}  // namespace consph
