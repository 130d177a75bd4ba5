// PLY, ascii and binary (either byte order). Vertex properties x y z, nx ny nz,
// s t / u v / texture_u texture_v, red green blue alpha; faces from the list
// vertex_indices (or vertex_index); other elements and properties are skipped.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>

#include "base/format.hpp"
#include "meshio/importers.hpp"
#include "meshio/text_reader.hpp"

namespace surfdeform::meshio {
namespace {

enum class Type { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

std::optional<Type> ParseType(std::string_view s) {
  if (s == "char" || s == "int8") return Type::kInt8;
  if (s == "uchar" || s == "uint8") return Type::kUInt8;
  if (s == "short" || s == "int16") return Type::kInt16;
  if (s == "ushort" || s == "uint16") return Type::kUInt16;
  if (s == "int" || s == "int32") return Type::kInt32;
  if (s == "uint" || s == "uint32") return Type::kUInt32;
  if (s == "float" || s == "float32") return Type::kFloat32;
  if (s == "double" || s == "float64") return Type::kFloat64;
  return std::nullopt;
}

size_t SizeOf(Type t) {
  switch (t) {
    case Type::kInt8:
    case Type::kUInt8:
      return 1;
    case Type::kInt16:
    case Type::kUInt16:
      return 2;
    case Type::kInt32:
    case Type::kUInt32:
    case Type::kFloat32:
      return 4;
    case Type::kFloat64:
      return 8;
  }
  return 1;
}

// What a property's values become, decided once per element rather than by
// comparing names for every value.
enum class Role {
  kIgnored,
  kX,
  kY,
  kZ,
  kNx,
  kNy,
  kNz,
  kU,
  kV,
  kRed,
  kGreen,
  kBlue,
  kAlpha,
  kIndices
};

struct Property {
  std::string name;
  Type type = Type::kFloat32;
  bool is_list = false;
  Type count_type = Type::kUInt8;
  Role role = Role::kIgnored;
};

Role RoleOf(const std::string& n, bool is_vertex, bool is_face) {
  if (is_face)
    return n == "vertex_indices" || n == "vertex_index" ? Role::kIndices : Role::kIgnored;
  if (!is_vertex) return Role::kIgnored;
  if (n == "x") return Role::kX;
  if (n == "y") return Role::kY;
  if (n == "z") return Role::kZ;
  if (n == "nx") return Role::kNx;
  if (n == "ny") return Role::kNy;
  if (n == "nz") return Role::kNz;
  if (n == "s" || n == "u" || n == "texture_u" || n == "texture_s") return Role::kU;
  if (n == "t" || n == "v" || n == "texture_v" || n == "texture_t") return Role::kV;
  if (n == "red") return Role::kRed;
  if (n == "green") return Role::kGreen;
  if (n == "blue") return Role::kBlue;
  if (n == "alpha") return Role::kAlpha;
  return Role::kIgnored;
}

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> properties;
};

// A binary value of type T in host byte order as a double.
template <typename T>
double As(const unsigned char* raw) {
  T x;
  std::memcpy(&x, raw, sizeof x);
  return static_cast<double>(x);
}

// A binary value in host byte order as a double.
double Decode(Type type, const unsigned char* raw) {
  switch (type) {
    case Type::kInt8:
      return As<int8_t>(raw);
    case Type::kUInt8:
      return As<uint8_t>(raw);
    case Type::kInt16:
      return As<int16_t>(raw);
    case Type::kUInt16:
      return As<uint16_t>(raw);
    case Type::kInt32:
      return As<int32_t>(raw);
    case Type::kUInt32:
      return As<uint32_t>(raw);
    case Type::kFloat32:
      return As<float>(raw);
    case Type::kFloat64:
      return As<double>(raw);
  }
  return 0.0;
}

// A binary value of `type` at `at`, in the file's byte order.
double Load(const char* at, Type type, bool swap) {
  if (!swap) return Decode(type, reinterpret_cast<const unsigned char*>(at));
  unsigned char raw[8];
  const size_t size = SizeOf(type);
  for (size_t k = 0; k < size; ++k) raw[k] = static_cast<unsigned char>(at[size - 1 - k]);
  return Decode(type, raw);
}

enum class Encoding { kAscii, kLittle, kBig };

// Reads values from the body, bounds-checked.
class BodyReader {
 public:
  BodyReader(std::string_view body, Encoding encoding)
      : text_(body), bytes_(body), enc_(encoding) {}

  bool Read(Type type, double* out) {
    if (enc_ == Encoding::kAscii) {
      std::string_view tok;
      while (!NextToken(&line_, &tok)) {
        if (!text_.NextLine(&line_)) return false;
      }
      return ParseNumber(tok, out);
    }
    const size_t size = SizeOf(type);
    if (bytes_.size() < size) return false;
    *out = Load(bytes_.data(), type, swapped());
    bytes_.remove_prefix(size);
    return true;
  }

  // Binary only: the bytes not read yet, and skipping those a fast path consumed.
  std::string_view bytes() const { return bytes_; }
  void Skip(size_t n) { bytes_.remove_prefix(n); }
  bool swapped() const {
    return (enc_ == Encoding::kBig) == (std::endian::native == std::endian::little);
  }

  // Bytes (binary) or characters (ascii) left: a bound on how many values can follow.
  size_t remaining() const {
    return enc_ == Encoding::kAscii ? text_.rest().size() + line_.size() : bytes_.size();
  }

 private:
  TextReader text_;
  std::string_view line_;
  std::string_view bytes_;
  Encoding enc_;
};

Status PlyError(const std::string& what) { return InvalidArgument("PLY: " + what, "mesh"); }

// Stores a vertex property's value by its role (integer colours are 0-255).
void Assign(const Property& p, size_t r, double x, Mesh* mesh) {
  const bool integer = p.type != Type::kFloat32 && p.type != Type::kFloat64;
  switch (p.role) {
    case Role::kX:
      mesh->positions[r].x() = x;
      break;
    case Role::kY:
      mesh->positions[r].y() = x;
      break;
    case Role::kZ:
      mesh->positions[r].z() = x;
      break;
    case Role::kNx:
      mesh->normals[r].x() = x;
      break;
    case Role::kNy:
      mesh->normals[r].y() = x;
      break;
    case Role::kNz:
      mesh->normals[r].z() = x;
      break;
    case Role::kU:
      mesh->uv0[r].x() = x;
      break;
    case Role::kV:
      mesh->uv0[r].y() = x;
      break;
    case Role::kRed:
      mesh->colors[r][0] = integer ? x / 255.0 : x;
      break;
    case Role::kGreen:
      mesh->colors[r][1] = integer ? x / 255.0 : x;
      break;
    case Role::kBlue:
      mesh->colors[r][2] = integer ? x / 255.0 : x;
      break;
    case Role::kAlpha:
      mesh->colors[r][3] = integer ? x / 255.0 : x;
      break;
    case Role::kIgnored:
    case Role::kIndices:
      break;
  }
}

// Binary fast paths: they read the leading records of an element whose layout
// is plain, and return how many they read; the general loop reads the rest
// (and reports whatever is wrong there, with the same messages).
//
// Records of fixed-size properties only (typically the vertices).
size_t ReadFixedRecords(const std::vector<Property>& props, size_t count, BodyReader* body,
                        Mesh* mesh) {
  size_t stride = 0;
  for (const Property& p : props) {
    if (p.is_list) return 0;
    stride += SizeOf(p.type);
  }
  struct Field {
    const Property* property;
    size_t offset;
  };
  std::vector<Field> fields;
  size_t offset = 0;
  for (const Property& p : props) {
    if (p.role != Role::kIgnored) fields.push_back({&p, offset});
    offset += SizeOf(p.type);
  }
  const std::string_view bytes = body->bytes();
  const size_t n = stride == 0 ? 0 : std::min(count, bytes.size() / stride);
  const bool swap = body->swapped();
  // The common case, positions only as host-order floats: a tight loop.
  if (fields.size() == 3 && !swap && fields[0].property->role == Role::kX &&
      fields[1].property->role == Role::kY && fields[2].property->role == Role::kZ &&
      fields[0].property->type == Type::kFloat32 && fields[1].property->type == Type::kFloat32 &&
      fields[2].property->type == Type::kFloat32) {
    for (size_t r = 0; r < n; ++r) {
      const char* record = bytes.data() + r * stride;
      float xyz[3];
      for (int c = 0; c < 3; ++c) std::memcpy(&xyz[c], record + fields[c].offset, 4);
      mesh->positions[r] = Vec3(xyz[0], xyz[1], xyz[2]);
    }
    body->Skip(n * stride);
    return n;
  }
  for (size_t r = 0; r < n; ++r) {
    const char* record = bytes.data() + r * stride;
    for (const Field& f : fields) {
      Assign(*f.property, r, Load(record + f.offset, f.property->type, swap), mesh);
    }
  }
  body->Skip(n * stride);
  return n;
}

// Faces that are only a list of 8-bit count and 32-bit indices, while each is
// a triangle of vertices that exist.
size_t ReadTriangleRecords(const std::vector<Property>& props, size_t count, BodyReader* body,
                           Mesh* mesh) {
  if (props.size() != 1 || !props[0].is_list || props[0].role != Role::kIndices) return 0;
  const Property& p = props[0];
  if (p.count_type != Type::kUInt8 && p.count_type != Type::kInt8) return 0;
  if (p.type != Type::kInt32 && p.type != Type::kUInt32) return 0;
  const std::string_view bytes = body->bytes();
  const bool swap = body->swapped();
  const size_t vertices = mesh->positions.size();
  size_t r = 0, at = 0;
  for (; r < count && at + 13 <= bytes.size() && bytes[at] == 3; ++r, at += 13) {
    std::array<uint32_t, 3> t;
    std::memcpy(t.data(), bytes.data() + at + 1, 12);
    bool valid = true;
    for (uint32_t& index : t) {
      if (swap) index = __builtin_bswap32(index);
      // A negative int32 reads as an unsigned value >= 2^31: out of range too.
      valid &= index < vertices;
    }
    if (!valid) break;
    mesh->triangles.push_back(t);
  }
  body->Skip(at);
  return r;
}

// The header: the body's encoding and its elements, in order. Free text
// without "comment" becomes a warning.
struct PlyHeader {
  Encoding encoding = Encoding::kAscii;
  std::vector<Element> elements;
};

Result<Property> ParseProperty(std::string_view line, int ln) {
  std::string_view tok;
  Property p;
  if (!NextToken(&line, &tok)) return LineError(ln, "a property needs a type");
  if (tok == "list") {
    std::string_view ct, it;
    if (!NextToken(&line, &ct) || !NextToken(&line, &it)) {
      return LineError(ln, "a list property needs two types");
    }
    const auto count_type = ParseType(ct), item_type = ParseType(it);
    if (!count_type || !item_type) return LineError(ln, "unknown property type");
    p.is_list = true;
    p.count_type = *count_type;
    p.type = *item_type;
  } else {
    const auto type = ParseType(tok);
    if (!type) return LineError(ln, "unknown property type");
    p.type = *type;
  }
  if (!NextToken(&line, &tok)) return LineError(ln, "a property needs a name");
  p.name = tok;
  return p;
}

Result<PlyHeader> ReadHeader(TextReader& header, std::vector<std::string>* warnings) {
  std::string_view line, tok;
  header.NextLine(&line);  // "ply"
  std::optional<Encoding> encoding;
  PlyHeader h;
  bool ended = false;
  while (header.NextLine(&line)) {
    const int ln = header.line_number();
    if (!NextToken(&line, &tok)) continue;
    if (tok == "end_header") {
      ended = true;
      break;
    }
    if (tok == "comment" || tok == "obj_info") continue;
    if (tok == "format") {
      NextToken(&line, &tok);
      if (tok == "ascii")
        encoding = Encoding::kAscii;
      else if (tok == "binary_little_endian")
        encoding = Encoding::kLittle;
      else if (tok == "binary_big_endian")
        encoding = Encoding::kBig;
      else
        return LineError(ln, "unknown PLY format");
    } else if (tok == "element") {
      Element e;
      std::string_view count;
      int64_t c;
      if (!NextToken(&line, &tok) || !NextToken(&line, &count) || !ParseNumber(count, &c) ||
          c < 0) {
        return LineError(ln, "an element needs a name and a count");
      }
      e.name = tok;
      e.count = static_cast<size_t>(c);
      h.elements.push_back(e);
    } else if (tok == "property") {
      if (h.elements.empty()) return LineError(ln, "a property before any element");
      SURFDEFORM_ASSIGN_OR_RETURN(Property p, ParseProperty(line, ln));
      h.elements.back().properties.push_back(p);
    } else {
      // Some exporters write free text without "comment": skip it.
      warnings->push_back("PLY header line " + std::to_string(ln) + " ignored");
    }
  }
  if (!ended) return PlyError("no end_header");
  if (!encoding) return PlyError("no format line");
  h.encoding = *encoding;
  return h;
}

// A count the rest of the file cannot hold is refused before allocating:
// every record takes at least one byte (binary) or two characters (ascii).
Status CheckRecordCount(const Element& e, Encoding encoding, size_t remaining) {
  size_t min_record = 0;
  for (const Property& p : e.properties) {
    min_record += p.is_list ? SizeOf(p.count_type) : SizeOf(p.type);
  }
  if (encoding == Encoding::kAscii) min_record = 2 * e.properties.size();
  // Records of no properties hold nothing, so no size bounds their count:
  // 10^14 of them once kept a worker busy for good (found by the import
  // fuzzer).
  if (e.properties.empty() && e.count > 0) {
    return PlyError("element " + e.name + " declares " + std::to_string(e.count) +
                    " records but no properties");
  }
  if (min_record > 0 && e.count > remaining / min_record) {
    return PlyError("element " + e.name + " claims " + std::to_string(e.count) +
                    " records, more than the file can hold");
  }
  return Status::Ok();
}

// One list property of record `r` of `e`, read one value at a time: a
// face's corners become triangles; other lists are skipped.
Status ReadList(const Element& e, const Property& p, size_t r, BodyReader& body, Mesh* mesh) {
  double count;
  if (!body.Read(p.count_type, &count)) return PlyError("the file ends inside " + e.name);
  if (!(count >= 0) || count > kMaxPolygon || count != std::floor(count)) {
    return PlyError(Format("%s %zu has a list of %.17g items (a whole number, at most %d)",
                           e.name.c_str(), r, count, static_cast<int>(kMaxPolygon)));
  }
  uint32_t poly[kMaxPolygon];
  const size_t n = static_cast<size_t>(count);
  for (size_t k = 0; k < n; ++k) {
    double index;
    if (!body.Read(p.type, &index)) return PlyError("the file ends inside " + e.name);
    if (p.role == Role::kIndices) {
      if (!(index >= 0) || index >= static_cast<double>(mesh->positions.size())) {
        // As written: an index past any integer (or NaN) cannot be converted.
        return PlyError(
            Format("face %zu uses vertex %.17g of %zu", r, index, mesh->positions.size()));
      }
      poly[k] = static_cast<uint32_t>(index);
    }
  }
  if (p.role == Role::kIndices) {
    if (n < 3) return PlyError("face " + std::to_string(r) + " has fewer than 3 corners");
    Vec3 corner_positions[kMaxPolygon];
    for (size_t k = 0; k < n; ++k) corner_positions[k] = mesh->positions[poly[k]];
    AppendPolygon(poly, corner_positions, n, mesh);
  }
  return Status::Ok();
}

// Every record of element `e` into `mesh`: vertices' attributes, faces'
// triangles; other elements are read past.
Status ReadElement(const Element& e, Encoding encoding, const ImportLimits& limits,
                   BodyReader& body, Mesh* mesh) {
  SURFDEFORM_RETURN_IF_ERROR(CheckRecordCount(e, encoding, body.remaining()));
  const bool is_vertex = e.name == "vertex";
  const bool is_face = e.name == "face";
  if (is_vertex) {
    SURFDEFORM_RETURN_IF_ERROR(CheckLimit("vertices", e.count, limits.max_vertices));
    mesh->positions.assign(e.count, Vec3::Zero());
  }
  if (is_face) {
    SURFDEFORM_RETURN_IF_ERROR(CheckLimit("faces", e.count, limits.max_triangles));
    mesh->triangles.reserve(e.count);
  }
  std::vector<Property> props = e.properties;
  for (Property& p : props) p.role = RoleOf(p.name, is_vertex, is_face);
  auto has = [&props](std::initializer_list<Role> roles) {
    for (const Property& p : props)
      if (std::find(roles.begin(), roles.end(), p.role) != roles.end()) return true;
    return false;
  };
  // Any component allocates its attribute (a file may name "ny" but no "nx"),
  // by the same roles that Assign writes.
  if (has({Role::kNx, Role::kNy, Role::kNz})) mesh->normals.assign(e.count, Vec3::Zero());
  if (has({Role::kU, Role::kV})) mesh->uv0.assign(e.count, Vec2::Zero());
  if (has({Role::kRed, Role::kGreen, Role::kBlue, Role::kAlpha})) {
    mesh->colors.assign(e.count, Vec4(0, 0, 0, 1));
  }
  size_t r = 0;
  if (encoding != Encoding::kAscii) {
    r = is_face ? ReadTriangleRecords(props, e.count, &body, mesh)
                : ReadFixedRecords(props, e.count, &body, mesh);
  }
  for (; r < e.count; ++r) {
    for (const Property& p : props) {
      if (p.is_list) {
        SURFDEFORM_RETURN_IF_ERROR(ReadList(e, p, r, body, mesh));
        continue;
      }
      double x;
      if (!body.Read(p.type, &x)) return PlyError("the file ends inside " + e.name);
      Assign(p, r, x, mesh);
    }
  }
  if (is_face) {
    return CheckLimit("triangles", mesh->triangles.size(), limits.max_triangles);
  }
  return Status::Ok();
}

}  // namespace

Result<ImportedMesh> ReadPly(std::string_view bytes, const ImportLimits& limits) {
  ImportedMesh out;
  TextReader header(bytes);
  SURFDEFORM_ASSIGN_OR_RETURN(const PlyHeader h, ReadHeader(header, &out.warnings));
  BodyReader body(header.rest(), h.encoding);
  for (const Element& e : h.elements) {
    SURFDEFORM_RETURN_IF_ERROR(ReadElement(e, h.encoding, limits, body, &out.mesh));
  }
  for (Vec3& nrm : out.mesh.normals) {
    const double len = nrm.norm();
    nrm = len > 0.0 ? Vec3(nrm / len) : Vec3::UnitZ();
  }
  return out;
}

}  // namespace surfdeform::meshio
