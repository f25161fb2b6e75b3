#include "Simulation/ResourceEstimate.h"

#include <unistd.h>

#include <climits>
#include <cmath>
#include <cstdio>

#include "Simulation/Scene.h"
#include "Utilities/Error.h"

namespace consph {

double defaultMaxParticles() {
  const double pages = double(sysconf(_SC_PHYS_PAGES)), pageSize = double(sysconf(_SC_PAGE_SIZE));
  const double memory = pages > 0 && pageSize > 0 ? pages * pageSize : 8e9;  // unknown: assume 8 GB
  return std::floor(0.5 * memory / kBytesPerFluidParticle);
}

namespace {
std::string number(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", x);
  return buffer;
}
std::string gigabytes(double bytes) { return number(bytes / 1e9) + " GB"; }
}  // namespace

void refuseIfTooLarge(const ResourceEstimate& e, double maxParticles) {
  const bool byDefault = maxParticles <= 0;
  const double limit = byDefault ? defaultMaxParticles() : maxParticles;
  std::string needs = "the scene needs about " + number(e.fluidParticles) + " fluid particles";
  if (e.boundary.samples > 0) needs += ", " + number(e.boundary.samples) + " boundary samples";
  if (e.boundary.cells > 0) needs += ", " + number(e.boundary.cells) + " volume-map cells";
  needs += " (~" + gigabytes(e.bytes()) + ")";
  const double maxIndex = double(UINT32_MAX);
  if (!(e.fluidParticles <= maxIndex) || !(e.boundary.samples <= maxIndex) || !(e.boundary.cells <= double(INT_MAX)))
    throw InputError(needs + ": more than a 32-bit index holds; use fewer or larger particles");
  if (!(e.bytes() <= limit * kBytesPerFluidParticle))
    throw InputError(needs + ", more than the limit of " + number(limit) + " particles (~" +
                     gigabytes(limit * kBytesPerFluidParticle) +
                     (byDefault ? ", half this machine's memory" : "") +
                     "); raise it with --max-particles N or simulation.maxParticles");
}

int checkedCount(double count, const std::string& what) {
  if (!(count >= 0 && count <= double(INT_MAX))) throw InputError(what + ": " + number(count) + " samples along one side is more than fits");
  return int(count);
}

}  // namespace consph
