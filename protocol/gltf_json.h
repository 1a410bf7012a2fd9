// The JSON of a glTF 2.0 file: a .gltf's text, or the JSON chunk of a .glb. For what
// Assimp's glTF importer reads wrongly or not at all (docs/import.md says which).
#pragma once

#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

namespace bumprad {

bool is_gltf_file(const std::filesystem::path& file);

// Throws std::runtime_error naming what is wrong (not readable, not a glTF binary, bad JSON).
nlohmann::json read_gltf_json(const std::filesystem::path& file);

// The first camera's vertical field of view (radians) and aspect ratio (0 where the file
// gives none), when it is a perspective camera.
struct GltfPerspective {
  double yfov, aspect;
};
std::optional<GltfPerspective> first_perspective_camera(const nlohmann::json& gltf);

// KHR_materials_emissive_strength of material `index`, where it has one (Assimp 5.2 does
// not read it).
std::optional<double> gltf_emissive_strength(const nlohmann::json& gltf, std::size_t index);

}  // namespace bumprad
