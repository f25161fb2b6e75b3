#include "Simulation/FrameFormat.h"

#include "Utilities/Error.h"

namespace consph {

const char* frameFormatName(FrameFormat format) {
  switch (format) {
    case FrameFormat::Vtu: return "vtu";
    case FrameFormat::Bgeo: return "bgeo";
    case FrameFormat::Ply: return "ply";
  }
  return "?";
}

FrameFormat frameFormatFromName(const std::string& name) {
  for (FrameFormat f : {FrameFormat::Vtu, FrameFormat::Bgeo, FrameFormat::Ply})
    if (name == frameFormatName(f)) return f;
  throw InputError("unknown frame format '" + name + "'; valid are: bgeo, ply, vtu");
}

const char* frameExtension(FrameFormat format) {
  switch (format) {
    case FrameFormat::Vtu: return ".vtu";
    case FrameFormat::Bgeo: return ".bgeo.gz";
    case FrameFormat::Ply: return ".ply";
  }
  return "";
}

FrameFormat frameFormatOfPath(const std::string& path, bool& compressed) {
  auto endsWith = [&](const std::string& suffix) {
    return path.size() >= suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  compressed = endsWith(".bgeo.gz");
  if (compressed || endsWith(".bgeo")) return FrameFormat::Bgeo;
  if (endsWith(".ply")) return FrameFormat::Ply;
  // .vtu, and any other name (/dev/stdout, a FIFO): VTU, as every frame was before BGEO and PLY.
  return FrameFormat::Vtu;
}

}  // namespace consph
