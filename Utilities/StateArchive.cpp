#include "Utilities/StateArchive.h"

namespace consph {

namespace {
const std::string kMagic = "consph-state 1\n";
}

void StateWriter::putBytes(const std::string& name, const void* data, std::size_t bytes) {
  const std::uint32_t length = std::uint32_t(name.size());
  const std::uint64_t size = bytes;
  bytes_.append(reinterpret_cast<const char*>(&length), sizeof(length));
  bytes_.append(name);
  bytes_.append(reinterpret_cast<const char*>(&size), sizeof(size));
  if (bytes > 0) bytes_.append(static_cast<const char*>(data), bytes);
}

StateReader::StateReader(const std::string& bytes, std::string file) : file_(std::move(file)) {
  if (bytes.compare(0, kMagic.size(), kMagic) != 0) throw InputError(file_ + ": not a consph checkpoint (no 'consph-state 1' header)");
  std::size_t at = kMagic.size();
  auto take = [&](void* out, std::size_t n) {
    if (bytes.size() - at < n) throw InputError(file_ + ": the checkpoint is cut short (a partial or damaged file)");
    std::memcpy(out, bytes.data() + at, n);
    at += n;
  };
  while (at < bytes.size()) {
    std::uint32_t length = 0;
    take(&length, sizeof(length));
    std::string name(length, '\0');
    take(name.data(), length);
    std::uint64_t size = 0;
    take(&size, sizeof(size));
    if (bytes.size() - at < size) throw InputError(file_ + ": the checkpoint is cut short (a partial or damaged file)");
    std::string block(std::size_t(size), '\0');
    take(block.data(), std::size_t(size));
    blocks_[name] = std::move(block);
  }
}

const std::string& StateReader::bytes(const std::string& name) const {
  auto it = blocks_.find(name);
  if (it == blocks_.end()) throw InputError(file_ + ": the checkpoint has no '" + name + "' (written by another version or scene?)");
  return it->second;
}

const std::string& StateReader::sized(const std::string& name, std::size_t n) const {
  const std::string& b = bytes(name);
  if (b.size() != n) throw InputError(file_ + ": block '" + name + "' has " + std::to_string(b.size()) + " bytes, expected " + std::to_string(n));
  return b;
}

std::vector<std::string> StateReader::names() const {
  std::vector<std::string> out;
  for (auto& [name, block] : blocks_) out.push_back(name);
  return out;
}

}  // namespace consph
