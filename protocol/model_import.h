// Models from modelling tools, read with Assimp (glTF 2.0, OBJ with MTL, FBX, COLLADA, PLY and
// the other formats it reads): each mesh instance with its node transform, per-vertex
// texture coordinates and shading normals, its material's base colour and emission, and the
// file's camera, as a scene for bumprad to solve. docs/import.md maps every field.
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "solver/scene/scene.h"

namespace bumprad {

// A model that cannot be used as given; the message names the file and, where there is one,
// the mesh or material.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ImportedModel {
  std::vector<Material> materials;
  std::vector<BumpFunction> bumps;    // the materials' normal maps, named "<material>/normal"
  std::vector<Object> objects;        // triangle meshes; indices into `materials` and `bumps`
  std::vector<PunctualLight> lights;  // KHR_lights_punctual (and other formats' lights)
  std::optional<Camera> camera;       // the file's first camera
  std::vector<std::string> warnings;  // what was dropped or assumed, naming the mesh
};

// Whether Assimp reads files with this name's extension (.glb, .gltf, .obj, .fbx, ...).
bool is_model_file(const std::filesystem::path& file);

// Throws ModelError. Textures resolve from the model's directory; with `confine`, one that
// lies outside that directory (a server's asset directory, a scene's own files) is refused.
// They are decoded within `budget` (the scene's), or within the per-image pixel limit.
ImportedModel import_model(const std::filesystem::path& file,
                           const std::optional<std::filesystem::path>& confine = {},
                           ImageBudget* budget = nullptr);

// Moves the model by `to_world` (positions; normals by its inverse transpose; a mirroring
// one turns the triangles' winding back; lights and camera follow).
void transform_model(ImportedModel& model, const glm::dmat4& to_world);

}  // namespace bumprad
