// tinygltf's implementation, compiled here rather than taken from Debian's
// libtinygltf (whose build crashes in ~TinyGLTF() when used from our objects),
// and built without file system access and without image codecs: external
// URIs cannot be read and images cannot be decoded, whatever the input says
// (docs/RELIABILITY.md). The same definitions apply to every file of this library
// (see CMakeLists.txt).
// tinygltf 2.7.0 with TINYGLTF_NO_FS still compiles its file writers (never
// called here) without including <fstream> itself.
#include <fstream>

#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
