// gzip compression (RFC 1952) through zlib: .bgeo.gz frames, which Houdini and partio open as
// they are.
#pragma once
#include <string>

namespace consph {

// The gzip stream of `data` at zlib's `level` (1 fast ... 9 small; 6 is zlib's default).
std::string gzipCompress(const std::string& data, int level = 6);

}  // namespace consph
