// One object of an exported frame, the cloth or a sphere, as plain arrays the writers
// (mesh_writers.h) put into a file: float32 points, triangles, per-vertex fields.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/model/model.h"
#include "core/model/state.h"

namespace clothsim {

struct VertexField {
  std::string name;           // "velocity", "speed", "strain", "error"
  int components = 1;         // 1 or 3
  std::vector<float> values;  // (components x N)
};

struct MeshPart {
  std::string name;                      // "cloth", "sphere0"
  std::vector<float> points;             // (3 x N) m
  std::vector<std::uint32_t> triangles;  // (3 x T) indices into points, CCW seen from outside
  std::vector<VertexField> fields;       // per vertex
};

// The cloth of `bodies` (its x and v; particles first): the model's triangles, and the fields
// velocity (m/s), speed (m/s), strain (view/vertex_fields.h), and error (m) when given.
MeshPart cloth_part(const Model& model, const State& bodies, const std::vector<float>* error);

// Sphere `s` of `bodies` as a closed UV sphere of its radius around its centre (kSphereRings
// rings of kSphereSegments quads, triangulated), with its velocity on every vertex.
MeshPart sphere_part(const Model& model, const State& bodies, int s);
inline constexpr int kSphereRings = 12, kSphereSegments = 24;

}  // namespace clothsim
