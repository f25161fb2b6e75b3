// Built volume maps kept on disk, so that a scene's second run loads its maps instead of
// computing them again (a two-dragon scene: minutes). A map is stored as
// DIRECTORY/volumemap_vN_KEY.state (Utilities/StateArchive.h), N the format version (maps of
// other versions are removed when a map is stored: they could never load), KEY a 64-bit FNV-1a
// hash of everything that changes the map: the format version, the build's precision, the object's
// world-space mesh (so its transform too), box and inversion, the kernel radius, the cell size,
// the surface offset and the thickness. The file repeats those inputs and a load checks them, so a
// hash collision or a stale file is rebuilt, never used. Files are written under a unique temporary
// name and renamed: runs that share a cache never see half a file.
#pragma once
#include <memory>
#include <string>

#include "Boundary/VolumeMap.h"
#include "Utilities/Log.h"

namespace consph {

class VolumeMapCache {
 public:
  // `directory` empty: no cache, every map is built.
  VolumeMapCache(std::string directory, LogSink log);

  // The map of `object` with these parameters: loaded when the cache holds it, else built (and stored).
  std::unique_ptr<VolumeMap> obtain(const BoundaryObject& object, const CubicSplineKernel& kernel, Real cellSize, Real surfaceOffset);

  std::size_t loads() const { return loads_; }
  std::size_t builds() const { return builds_; }
  // The cache file that holds (or would hold) this map; empty without a cache.
  std::string pathOf(const BoundaryObject& object, const CubicSplineKernel& kernel, Real cellSize, Real surfaceOffset) const;

 private:
  std::string directory_;
  LogSink log_;
  std::size_t loads_ = 0, builds_ = 0;
};

}  // namespace consph
