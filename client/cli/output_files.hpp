// Files the command-line client reads and writes: the output format that a
// file's extension asks for, local decoding of Draco into OBJ or PLY, and
// writes that never leave a half-written output behind (resumable batches).
// Uses meshio (Eigen), never httplib.
#pragma once

#include <optional>
#include <string>

namespace surfdeform::cli {

enum class OutputKind { kDrc, kGlb, kObj, kPly };

// From the extension (case-insensitive): .drc, .glb, .obj, .ply.
std::optional<OutputKind> OutputKindOf(const std::string& path);
const char* OutputExtension(OutputKind kind);  // ".drc", ...

// True for the extensions of the mesh formats the server reads.
bool IsMeshFileName(const std::string& path);

// A .drc received from the server as OBJ or PLY bytes (kind kObj or kPly).
// False with a message when the bytes do not decode.
bool DracoTo(const std::string& drc, OutputKind kind, std::string* out, std::string* error);

bool ReadFileBytes(const std::string& path, std::string* out, std::string* error);
// Writes to a temporary file beside `path`, then renames it into place.
bool WriteFileAtomically(const std::string& path, const std::string& bytes, std::string* error);

}  // namespace surfdeform::cli
