#include "meshio/print_formats.hpp"

#include <Model/COM/NMR_DLLInterfaces.h>

#include <cstring>
#include <vector>

namespace surfdeform {
namespace {

// A lib3mf instance released when it goes out of scope.
struct Held {
  NMR::PLib3MFBase* p = nullptr;
  ~Held() {
    if (p != nullptr) NMR::lib3mf_release(p);
  }
};

void PutFloat(std::string* out, double x) {
  const float f = static_cast<float>(x);
  char bytes[4];
  std::memcpy(bytes, &f, 4);
  out->append(bytes, 4);
}

Status Lib3mfError(const char* what) {
  return Status(ErrorCode::kInternal, std::string("the 3MF package could not be ") + what);
}

}  // namespace

std::string WriteBinaryStl(const Mesh& mesh) {
  std::string out(80, ' ');
  const char title[] = "binary STL from surfdeform, millimetres";
  std::memcpy(out.data(), title, sizeof title - 1);
  const uint32_t count = static_cast<uint32_t>(mesh.triangles.size());
  out.append(reinterpret_cast<const char*>(&count), 4);
  out.reserve(84 + 50 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.positions[t[0]];
    const Vec3& b = mesh.positions[t[1]];
    const Vec3& c = mesh.positions[t[2]];
    const Vec3 cross = (b - a).cross(c - a);
    const double len = cross.norm();
    const Vec3 n = len > 0 ? Vec3(cross / len) : Vec3::Zero();
    for (const Vec3* p : {&n, &a, &b, &c}) {
      for (int k = 0; k < 3; ++k) PutFloat(&out, (*p)[k]);
    }
    out.append(2, '\0');  // attribute byte count
  }
  return out;
}

Result<std::string> Write3mf(const Mesh& mesh, const std::string& name) {
  Held model, object, item, writer;
  if (NMR::lib3mf_createmodel(&model.p) != 0) return Lib3mfError("made");
  NMR::lib3mf_model_setunit(model.p, NMR::MODELUNIT_MILLIMETER);
  if (NMR::lib3mf_model_addmeshobject(model.p, &object.p) != 0) return Lib3mfError("made");
  NMR::lib3mf_object_setnameutf8(object.p, name.c_str());
  std::vector<NMR::MODELMESHVERTEX> vertices(mesh.positions.size());
  for (size_t k = 0; k < mesh.positions.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      vertices[k].m_fPosition[c] = static_cast<float>(mesh.positions[k][c]);
    }
  }
  std::vector<NMR::MODELMESHTRIANGLE> triangles(mesh.triangles.size());
  for (size_t k = 0; k < mesh.triangles.size(); ++k) {
    for (int c = 0; c < 3; ++c) triangles[k].m_nIndices[c] = mesh.triangles[k][c];
  }
  if (NMR::lib3mf_meshobject_setgeometry(object.p, vertices.data(),
                                         static_cast<DWORD>(vertices.size()), triangles.data(),
                                         static_cast<DWORD>(triangles.size())) != 0) {
    return Lib3mfError("filled");
  }
  if (NMR::lib3mf_model_addbuilditem(model.p, object.p, nullptr, &item.p) != 0 ||
      NMR::lib3mf_model_querywriter(model.p, "3mf", &writer.p) != 0) {
    return Lib3mfError("made");
  }
  ULONG64 size = 0;
  if (NMR::lib3mf_writer_getstreamsize(writer.p, &size) != 0) return Lib3mfError("written");
  std::string out(size, '\0');
  if (NMR::lib3mf_writer_writetobuffer(writer.p, reinterpret_cast<BYTE*>(out.data()), size) != 0) {
    return Lib3mfError("written");
  }
  return out;
}

Result<ThreeMfContents> Read3mfContents(std::string_view bytes) {
  Held model, reader, objects, items;
  if (NMR::lib3mf_createmodel(&model.p) != 0 ||
      NMR::lib3mf_model_queryreader(model.p, "3mf", &reader.p) != 0) {
    return Lib3mfError("read");
  }
  std::string copy(bytes);
  if (NMR::lib3mf_reader_readfrombuffer(reader.p, reinterpret_cast<BYTE*>(copy.data()),
                                        copy.size()) != 0) {
    return Status(ErrorCode::kInvalidArgument, "not a 3MF package lib3mf reads");
  }
  ThreeMfContents c;
  DWORD unit = 0;
  NMR::lib3mf_model_getunit(model.p, &unit);
  switch (unit) {
    case NMR::MODELUNIT_MICROMETER:
      c.unit = "micron";
      break;
    case NMR::MODELUNIT_MILLIMETER:
      c.unit = "millimeter";
      break;
    case NMR::MODELUNIT_CENTIMETER:
      c.unit = "centimeter";
      break;
    case NMR::MODELUNIT_INCH:
      c.unit = "inch";
      break;
    case NMR::MODELUNIT_FOOT:
      c.unit = "foot";
      break;
    case NMR::MODELUNIT_METER:
      c.unit = "meter";
      break;
    default:
      c.unit = "unknown";
  }
  if (NMR::lib3mf_model_getmeshobjects(model.p, &objects.p) != 0) return Lib3mfError("read");
  BOOL more = false;
  while (NMR::lib3mf_resourceiterator_movenext(objects.p, &more) == 0 && more) {
    Held object;
    if (NMR::lib3mf_resourceiterator_getcurrent(objects.p, &object.p) != 0) break;
    DWORD v = 0, t = 0;
    NMR::lib3mf_meshobject_getvertexcount(object.p, &v);
    NMR::lib3mf_meshobject_gettrianglecount(object.p, &t);
    ++c.objects;
    c.vertices += v;
    c.triangles += t;
  }
  if (NMR::lib3mf_model_getbuilditems(model.p, &items.p) == 0) {
    while (NMR::lib3mf_builditemiterator_movenext(items.p, &more) == 0 && more) ++c.build_items;
  }
  return c;
}

}  // namespace surfdeform
