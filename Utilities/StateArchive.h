// A binary file of named byte blocks: what a checkpoint is made of. Layout: the magic line
// "consph-state 1\n", then per block a uint32 name length, the name, a uint64 byte count and the
// bytes (machine byte order: a checkpoint is restarted by the same build on the same kind of
// machine, which is what "bit for bit" needs anyway).
#pragma once
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "Utilities/Error.h"

namespace consph {

class StateWriter {
 public:
  void putBytes(const std::string& name, const void* data, std::size_t bytes);
  template <class T>
  void put(const std::string& name, const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    putBytes(name, &value, sizeof(T));
  }
  template <class T>
  void putVector(const std::string& name, const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    putBytes(name, values.data(), values.size() * sizeof(T));
  }
  void putString(const std::string& name, const std::string& text) { putBytes(name, text.data(), text.size()); }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_ = "consph-state 1\n";
};

class StateReader {
 public:
  // Parses `bytes` read from `file` (named in errors); InputError when it is no state file or is cut short.
  StateReader(const std::string& bytes, std::string file);
  bool has(const std::string& name) const { return blocks_.count(name) > 0; }
  // The block `name`; InputError naming the file when it is missing.
  const std::string& bytes(const std::string& name) const;
  template <class T>
  T get(const std::string& name) const {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::string& b = sized(name, sizeof(T));
    T value;
    std::memcpy(&value, b.data(), sizeof(T));
    return value;
  }
  template <class T>
  std::vector<T> getVector(const std::string& name) const {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::string& b = bytes(name);
    if (b.size() % sizeof(T) != 0) throw InputError(file_ + ": block '" + name + "' has a size that fits no array of its type");
    std::vector<T> values(b.size() / sizeof(T));
    if (!values.empty()) std::memcpy(values.data(), b.data(), b.size());
    return values;
  }
  // Block names in sorted order.
  std::vector<std::string> names() const;
  const std::string& file() const { return file_; }

 private:
  const std::string& sized(const std::string& name, std::size_t bytes) const;
  std::string file_;
  std::map<std::string, std::string> blocks_;
};

}  // namespace consph
