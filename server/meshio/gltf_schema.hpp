// The glTF 2.0 schema's rules for the objects a mesh is read through
// (accessors, buffer views, buffers), checked on the JSON before tinygltf
// reads it, so that a file that breaks one is refused with the object and
// field named ("accessors[2].count must be an integer of at least 1, got
// -1"), not as "not a valid GLB file", and so that tinygltf never reads a
// value the schema forbids as another (a byteOffset of -12 as 0).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace surfdeform::meshio {

// The first rule `doc` breaks, as a message whose field path starts it
// ("accessors[2].count ..."), or empty. `field` receives that path.
std::string FirstGltfSchemaProblem(const nlohmann::json& doc, std::string* field);

}  // namespace surfdeform::meshio
