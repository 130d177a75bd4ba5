// One parse of a generated input, for tests/scaling/linear_parsers.sh: the
// input is made first, then only its parse runs between callgrind's
// collection toggles, so that valgrind counts the parser's instructions
// alone. The heap's peak during the parse is counted by this program's own
// operator new.
//
// Usage: scaling_probe SHAPE N   (scaling_probe --list: the shapes)
// Prints one line: shape, n, input bytes, status code, peak heap bytes.
#include <valgrind/callgrind.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <new>
#include <string>

#include "json/bounded_json.hpp"
#include "meshio/mesh_import.hpp"

namespace {

// The heap in use and its peak, through operator new (the containers of
// the parsers and of nlohmann's documents all allocate through it).
std::atomic<size_t> g_live{0};
std::atomic<size_t> g_peak{0};

void* Allocate(size_t n) {
  void* p = std::malloc(n + 16);
  if (p == nullptr) throw std::bad_alloc();
  *static_cast<size_t*>(p) = n;
  const size_t live = g_live.fetch_add(n) + n;
  size_t peak = g_peak.load();
  while (live > peak && !g_peak.compare_exchange_weak(peak, live)) {
  }
  return static_cast<char*>(p) + 16;
}

void Release(void* q) {
  if (q == nullptr) return;
  void* p = static_cast<char*>(q) - 16;
  g_live.fetch_sub(*static_cast<size_t*>(p));
  std::free(p);
}

}  // namespace

void* operator new(size_t n) { return Allocate(n); }
void* operator new[](size_t n) { return Allocate(n); }
void operator delete(void* p) noexcept { Release(p); }
void operator delete[](void* p) noexcept { Release(p); }
void operator delete(void* p, size_t) noexcept { Release(p); }
void operator delete[](void* p, size_t) noexcept { Release(p); }

namespace {

using surfdeform::ErrorCode;
using surfdeform::Status;

std::string Repeat(const std::string& piece, size_t n) {
  std::string out;
  out.reserve(piece.size() * n);
  for (size_t k = 0; k < n; ++k) out += piece;
  return out;
}

// A list of n pieces made by `piece(k)`, joined by commas.
std::string Joined(size_t n, const std::function<std::string(size_t)>& piece) {
  std::string out;
  for (size_t k = 0; k < n; ++k) {
    if (k > 0) out += ',';
    out += piece(k);
  }
  return out;
}

const char* kTriangleBuffer =
    "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";

// A glTF with one triangle's buffer and accessor, and the given extra
// members (after a comma) at its top level.
std::string Gltf(const std::string& accessors, const std::string& meshes, const std::string& nodes,
                 const std::string& scene_nodes, const std::string& extra = "") {
  return std::string(R"({"asset":{"version":"2.0"},"buffers":[{"uri":")") + kTriangleBuffer +
         R"(","byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[)" +
         accessors + R"(],"meshes":[)" + meshes + R"(],"nodes":[)" + nodes +
         R"(],"scenes":[{"nodes":[)" + scene_nodes + "]}]" + extra + "}";
}
const std::string kAccessor = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"})";
const std::string kPrimitive = R"({"attributes":{"POSITION":0}})";
const std::string kMesh = R"({"primitives":[)" + kPrimitive + "]}";

struct Shape {
  bool json;  // request JSON (else a mesh file)
  std::function<std::string(size_t)> make;
};

const std::map<std::string, Shape>& Shapes() {
  static const std::map<std::string, Shape> shapes = {
      // Request JSON: the shapes of the hostile round's report, and a real
      // request's.
      {"json_empty_objects",
       {true, [](size_t n) { return "{\"x\":[" + Joined(n, [](size_t) { return "{}"; }) + "]}"; }}},
      {"json_long_key_objects",
       {true,
        [](size_t n) {
          return "{\"" + std::string(4096, 'k') + "\":[" +
                 Joined(n, [](size_t) { return "{\"a\":{}}"; }) + "]}";
        }}},
      {"json_key_length",
       {true,
        [](size_t n) {
          return "{\"" + std::string(n * 16, 'k') + "\":[" +
                 Joined(1024, [](size_t) { return "{}"; }) + "]}";
        }}},
      {"json_numbers",
       {true,
        [](size_t n) {
          return "{\"x\":[" + Joined(n, [](size_t k) { return std::to_string(k) + ".25"; }) + "]}";
        }}},
      {"json_keys",
       {true,
        [](size_t n) {
          return "{" + Joined(n, [](size_t k) { return "\"k" + std::to_string(k) + "\":0"; }) + "}";
        }}},
      {"json_strings",
       {true,
        [](size_t n) {
          return "[" + Joined(n, [](size_t) { return std::string("\"abcdefgh\""); }) + "]";
        }}},
      {"json_nested",
       {true,
        [](size_t n) {
          return "[" +
                 Joined(n, [](size_t) { return std::string(30, '[') + std::string(30, ']'); }) +
                 "]";
        }}},
      {"json_grid_points",
       {true,
        [](size_t n) {
          return R"({"surface":{"kind":"grid","nu":)" + std::to_string(n) +
                 R"(,"nv":1,"points":[)" +
                 Joined(n, [](size_t k) { return "[" + std::to_string(k) + ".125,0.5,-0.25]"; }) +
                 "]}}";
        }}},
      // Mesh files, one structural axis each.
      {"obj_faces",
       {false,
        [](size_t n) {
          std::string s;
          for (size_t k = 0; k < n; ++k) s += "v " + std::to_string(k) + " 0 0\nv 0 1 0\nv 0 0 1\n";
          for (size_t k = 0; k < n; ++k) {
            const std::string b = std::to_string(3 * k + 1);
            s +=
                "f " + b + " " + std::to_string(3 * k + 2) + " " + std::to_string(3 * k + 3) + "\n";
          }
          return s;
        }}},
      {"obj_usemtl_names",
       {false,
        [](size_t n) {
          std::string s = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
          for (size_t k = 0; k < n; ++k) s += "usemtl m" + std::to_string(k) + "\n";
          return s + "f 1 2 3\n";
        }}},
      {"obj_groups",
       {false,
        [](size_t n) {
          std::string s = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
          for (size_t k = 0; k < n; ++k) s += "g part" + std::to_string(k) + "\nf 1 2 3\n";
          return s;
        }}},
      {"ply_faces",
       {false,
        [](size_t n) {
          std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(3 * n) +
                          "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                          std::to_string(n) +
                          "\nproperty list uchar int vertex_indices\nend_header\n";
          for (size_t k = 0; k < n; ++k) s += std::to_string(k) + " 0 0\n0 1 0\n0 0 1\n";
          for (size_t k = 0; k < n; ++k) {
            s += "3 " + std::to_string(3 * k) + " " + std::to_string(3 * k + 1) + " " +
                 std::to_string(3 * k + 2) + "\n";
          }
          return s;
        }}},
      {"stl_binary",
       {false,
        [](size_t n) {
          std::string s(80, ' ');
          const uint32_t count = static_cast<uint32_t>(n);
          s.append(reinterpret_cast<const char*>(&count), 4);
          for (size_t k = 0; k < n; ++k) {
            float f[12] = {0, 0, 1, static_cast<float>(k), 0, 0, 0, 1, 0, 0, 0, 1};
            s.append(reinterpret_cast<const char*>(f), sizeof f);
            s.append(2, '\0');
          }
          return s;
        }}},
      {"stl_ascii",
       {false,
        [](size_t n) {
          std::string s = "solid x\n";
          for (size_t k = 0; k < n; ++k) {
            s += "facet normal 0 0 1\nouter loop\nvertex " + std::to_string(k) +
                 " 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n";
          }
          return s + "endsolid x\n";
        }}},
      {"off_faces",
       {false,
        [](size_t n) {
          std::string s = "OFF\n" + std::to_string(3 * n) + " " + std::to_string(n) + " 0\n";
          for (size_t k = 0; k < n; ++k) s += std::to_string(k) + " 0 0\n0 1 0\n0 0 1\n";
          for (size_t k = 0; k < n; ++k) {
            s += "3 " + std::to_string(3 * k) + " " + std::to_string(3 * k + 1) + " " +
                 std::to_string(3 * k + 2) + "\n";
          }
          return s;
        }}},
      {"gltf_nodes",
       {false,
        [](size_t n) {
          return Gltf(kAccessor, kMesh, R"({"mesh":0})" + Repeat(R"(,{"name":"n"})", n),
                      Joined(n + 1, [](size_t k) { return std::to_string(k); }));
        }}},
      {"gltf_child_nodes",
       {false,
        [](size_t n) {
          // A chain: each node the child of the one before.
          return Gltf(
              kAccessor, kMesh,
              Joined(n,
                     [](size_t k) { return R"({"children":[)" + std::to_string(k + 1) + "]}"; }) +
                  R"(,{"mesh":0})",
              "0");
        }}},
      {"gltf_meshes",
       {false,
        [](size_t n) {
          return Gltf(kAccessor, Joined(n, [](size_t) { return kMesh; }), R"({"mesh":0})", "0");
        }}},
      {"gltf_accessors",
       {false,
        [](size_t n) {
          return Gltf(Joined(n, [](size_t) { return kAccessor; }), kMesh, R"({"mesh":0})", "0");
        }}},
      {"gltf_primitives",
       {false,
        [](size_t n) {
          return Gltf(kAccessor,
                      R"({"primitives":[)" + Joined(n, [](size_t) { return kPrimitive; }) + "]}",
                      R"({"mesh":0})", "0");
        }}},
      {"gltf_extras",
       {false,
        [](size_t n) {
          return Gltf(kAccessor, kMesh, R"({"mesh":0})", "0",
                      R"(,"extras":{"a":[)" +
                          Joined(n, [](size_t) { return std::string("{\"b\":[0,1]}"); }) + "]}");
        }}},
  };
  return shapes;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--list") {
    for (const auto& [name, shape] : Shapes()) std::printf("%s\n", name.c_str());
    return 0;
  }
  if (argc != 3 || Shapes().count(argv[1]) == 0) {
    std::fprintf(stderr, "usage: scaling_probe SHAPE N (--list: the shapes)\n");
    return 2;
  }
  const Shape& shape = Shapes().at(argv[1]);
  const size_t n = std::strtoull(argv[2], nullptr, 10);
  const std::string input = shape.make(n);
  surfdeform::ImportLimits import_limits;
  import_limits.max_bytes = 1u << 30;
  const size_t before = g_live.load();
  g_peak.store(before);
  Status status;
  CALLGRIND_TOGGLE_COLLECT;
  if (shape.json) {
    status = surfdeform::ParseBoundedJson(input, surfdeform::JsonLimits{}, "body").status();
  } else {
    status = surfdeform::ImportMesh(input, import_limits).status();
  }
  CALLGRIND_TOGGLE_COLLECT;
  std::printf("%s %zu bytes %zu code %s peak_heap %zu\n", argv[1], n, input.size(),
              surfdeform::ErrorCodeName(status.code()), g_peak.load() - before);
  return 0;
}
