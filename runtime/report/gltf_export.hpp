// `mechgen view --gltf`: the view's bodies and motion as binary glTF 2.0 (GLB), written against the
// Khronos specification (no library): a 12-byte header, a JSON chunk and a BIN chunk. One node
// per body (its shapes as triangle primitives in the body's frame, lines as LINES primitives,
// flat normals), under a root node that turns the model's up (against gravity) into glTF's +Y;
// one animation whose channels give every moving body's translation and rotation per sample
// (LINEAR samplers). glTF keys need strictly increasing times from 0 or later: rows that repeat
// a time (a walk's support change) keep the later one, and times start where the table starts
// (shifted to 0 only when it starts before 0). Numbers are float32, as glTF accessors are.
#pragma once

#include <string>

#include "report/view_scene.hpp"

namespace mechgen::report {

// The GLB file's bytes.
std::string gltf_binary(const ViewScene& scene);

}  // namespace mechgen::report
