// Type checks of a glTF document's JSON before tinygltf reads it. tinygltf drops a member of the
// wrong type without a word (a node whose "mesh" is "abc", 1.5 or -1 simply has no mesh,
// "translation": "x" is no translation, "children": [0, "a"] becomes [0]) and narrows integers
// to int (4294967295 becomes -1, which it takes for "absent"). Here every member the loader or
// tinygltf reads is checked for its JSON type and every index for being an integer naming an
// element that exists, each error naming the JSON path and the value:
//   nodes[3].mesh: expected a non-negative integer index, got "abc"
//   nodes[3].mesh = 99 does not exist (the file has 2 meshes)
// What the values mean (lengths of transforms, finite numbers, enums) is validate_gltf's job,
// on the parsed model.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include "core/result.h"

namespace ddgi {

Status check_gltf_json(const nlohmann::json& doc);

}  // namespace ddgi
