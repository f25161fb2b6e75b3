#include "Utilities/Gzip.h"

#include <zlib.h>

#include <algorithm>
#include <stdexcept>

namespace consph {

std::string gzipCompress(const std::string& data, int level) {
  z_stream z{};
  // windowBits 15 + 16: a gzip header and trailer instead of zlib's.
  if (deflateInit2(&z, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::runtime_error("zlib: deflateInit2 failed");
  std::string out;
  char buffer[1 << 16];
  std::size_t offset = 0;
  int status = Z_OK;
  // zlib counts in 32-bit uInt: a frame over 4 GiB goes in slices.
  while (status != Z_STREAM_END) {
    const std::size_t slice = std::min<std::size_t>(data.size() - offset, std::size_t(1) << 30);
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data() + offset));
    z.avail_in = uInt(slice);
    const bool last = offset + slice == data.size();
    do {
      z.next_out = reinterpret_cast<Bytef*>(buffer);
      z.avail_out = sizeof(buffer);
      status = deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
      if (status == Z_STREAM_ERROR) {
        deflateEnd(&z);
        throw std::runtime_error("zlib: deflate failed");
      }
      out.append(buffer, sizeof(buffer) - z.avail_out);
    } while (z.avail_out == 0);
    offset += slice;
  }
  deflateEnd(&z);
  return out;
}

}  // namespace consph
