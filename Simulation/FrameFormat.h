// The file formats of a run's frames (output.format) and how moving bodies go into them
// (output.bodies): VTU for ParaView, classic BGEO for Houdini, binary PLY for Blender.
#pragma once
#include <string>

namespace consph {

enum class FrameFormat { Vtu, Bgeo, Ply };

// Moving bodies per frame: their surfaces (a mesh per frame), or one point per body with its
// pose (P, orient, pivot: what Houdini's Copy to Points instances a shape with).
enum class BodyFrames { Meshes, Transforms };

// "vtu", "bgeo", "ply" (the scene's names).
const char* frameFormatName(FrameFormat format);
FrameFormat frameFormatFromName(const std::string& name);  // InputError for another name
// The file extension, with its dot: ".vtu", ".bgeo.gz" (gzip-compressed, as Houdini writes it), ".ply".
const char* frameExtension(FrameFormat format);
// The format a file name asks for by its extension (.bgeo, .bgeo.gz, .ply; any other: VTU);
// `compressed` is set for .bgeo.gz.
FrameFormat frameFormatOfPath(const std::string& path, bool& compressed);

}  // namespace consph
