#include "Utilities/LineFile.h"

#include <cerrno>
#include <cstring>

#include "Utilities/Error.h"

namespace consph {

LineFile::LineFile(const std::string& path, const std::string& header) : path_(path) {
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) throw OutputError("cannot write '" + path + "': " + std::strerror(errno));
  append(header);
}

LineFile::~LineFile() {
  if (file_) std::fclose(file_);
}

void LineFile::append(const std::string& line) {
  const std::string text = line + "\n";
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size() || std::fflush(file_) != 0)
    throw OutputError("write to '" + path_ + "' failed: " + std::strerror(errno));
}

}  // namespace consph
