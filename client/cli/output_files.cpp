#include "cli/output_files.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"

namespace surfdeform::cli {
namespace {

std::string LowerExtension(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace

std::optional<OutputKind> OutputKindOf(const std::string& path) {
  const std::string ext = LowerExtension(path);
  if (ext == ".drc") return OutputKind::kDrc;
  if (ext == ".glb") return OutputKind::kGlb;
  if (ext == ".obj") return OutputKind::kObj;
  if (ext == ".ply") return OutputKind::kPly;
  return std::nullopt;
}

const char* OutputExtension(OutputKind kind) {
  switch (kind) {
    case OutputKind::kDrc:
      return ".drc";
    case OutputKind::kGlb:
      return ".glb";
    case OutputKind::kObj:
      return ".obj";
    case OutputKind::kPly:
      return ".ply";
  }
  return "";
}

bool IsMeshFileName(const std::string& path) {
  const std::string ext = LowerExtension(path);
  for (const char* known : {".glb", ".gltf", ".drc", ".obj", ".ply", ".stl", ".off"}) {
    if (ext == known) return true;
  }
  return false;
}

bool DracoTo(const std::string& drc, OutputKind kind, std::string* out, std::string* error) {
  auto mesh = ImportMesh(drc);
  if (!mesh.ok()) {
    *error = "cannot decode the server's Draco reply: " + mesh.status().message();
    return false;
  }
  ExportOptions options;
  options.materials = mesh->materials;
  auto bytes = ExportMesh(mesh->mesh,
                          kind == OutputKind::kObj ? MeshFormat::kObj : MeshFormat::kPly, options);
  if (!bytes.ok()) {
    *error = "cannot write the decoded mesh: " + bytes.status().message();
    return false;
  }
  *out = std::move(*bytes);
  return true;
}

bool ReadFileBytes(const std::string& path, std::string* out, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *error = "cannot read " + path + ": " + std::strerror(errno);
    return false;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  *out = ss.str();
  return true;
}

bool WriteFileAtomically(const std::string& path, const std::string& bytes, std::string* error) {
  const std::string temp = path + ".part-" + std::to_string(::getpid());
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      *error = "cannot write " + path + ": " + std::strerror(errno);
      std::remove(temp.c_str());
      return false;
    }
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    *error = "cannot write " + path + ": " + std::strerror(errno);
    std::remove(temp.c_str());
    return false;
  }
  return true;
}

}  // namespace surfdeform::cli
