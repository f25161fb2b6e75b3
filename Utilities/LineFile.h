// A text file written a line at a time and flushed after every line, so a run that is killed
// keeps every line written before (probes.csv). Each line goes out in one write.
#pragma once
#include <cstdio>
#include <string>

namespace consph {

class LineFile {
 public:
  // Creates (truncates) `path` and writes `header` as its first line (or lines: a restarted
  // run's probes.csv starts with the rows it keeps).
  LineFile(const std::string& path, const std::string& header);
  ~LineFile();
  LineFile(const LineFile&) = delete;
  LineFile& operator=(const LineFile&) = delete;

  // Appends `line` and a newline, then flushes to the operating system.
  void append(const std::string& line);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
};

}  // namespace consph
