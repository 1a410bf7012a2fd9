#include "protocol/gltf_json.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

namespace bumprad {
namespace {

std::uint32_t little_endian_u32(const char* bytes) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | std::uint8_t(bytes[k]);
  return v;
}

}  // namespace

bool is_gltf_file(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  return ext == ".gltf" || ext == ".glb";
}

nlohmann::json read_gltf_json(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot be read");
  // A GLB is a 12-byte header, then its first chunk (length, type "JSON", data): only that
  // is read, not the binary buffers after it, which Assimp has read already.
  char header[20] = {};
  in.read(header, sizeof header);
  std::string text;
  if (in.gcount() >= 4 && std::memcmp(header, "glTF", 4) == 0) {
    const std::uint32_t length = little_endian_u32(header + 12);
    if (in.gcount() < 20 || little_endian_u32(header + 16) != 0x4E4F534Au ||
        length > std::filesystem::file_size(file) - 20)
      throw std::runtime_error("a glTF binary whose first chunk is not its JSON");
    text.resize(length);
    in.read(text.data(), std::streamsize(length));
  } else {
    text.assign(header, std::size_t(in.gcount()));
    text.append(std::istreambuf_iterator<char>(in), {});
  }
  if (in.bad()) throw std::runtime_error("cannot be read");
  nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
  if (json.is_discarded() || !json.is_object())
    throw std::runtime_error("its glTF JSON does not parse");
  return json;
}

std::optional<GltfPerspective> first_perspective_camera(const nlohmann::json& gltf) {
  const auto cameras = gltf.find("cameras");
  if (cameras == gltf.end() || !cameras->is_array() || cameras->empty()) return std::nullopt;
  const nlohmann::json& camera = cameras->front();
  const auto p = camera.find("perspective");
  if (!camera.is_object() || camera.value("type", "") != "perspective" || p == camera.end() ||
      !p->is_object() || !p->contains("yfov") || !(*p)["yfov"].is_number())
    return std::nullopt;
  const auto aspect = p->find("aspectRatio");
  return GltfPerspective{(*p)["yfov"].get<double>(),
                         aspect != p->end() && aspect->is_number() ? aspect->get<double>() : 0};
}

std::optional<double> gltf_emissive_strength(const nlohmann::json& gltf, std::size_t index) {
  const nlohmann::json::json_pointer at("/materials/" + std::to_string(index) +
                                        "/extensions/KHR_materials_emissive_strength/"
                                        "emissiveStrength");
  if (!gltf.contains(at) || !gltf[at].is_number()) return std::nullopt;
  return gltf[at].get<double>();
}

}  // namespace bumprad
