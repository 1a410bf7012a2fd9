#include "protocol/solution_json.h"

#include <nlohmann/json.hpp>

namespace bumprad {

std::string solution_to_json(const Scene& scene, const Mesh& mesh, std::span<const Rgb> radiosity,
                             const SolveStats& stats) {
  nlohmann::json elements = nlohmann::json::array();
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    elements.push_back({{"id", i},
                        {"object", scene.objects[e.object].name},
                        {"area", e.area},
                        {"radiosity", {radiosity[i].r, radiosity[i].g, radiosity[i].b}}});
  }
  nlohmann::json doc = {{"elements", std::move(elements)},
                        {"stats",
                         {{"shots", stats.shots},
                          {"elements", stats.elements},
                          {"seconds_solve", stats.seconds_solve},
                          {"unshot_fraction", stats.unshot_fraction},
                          {"seconds_texture", stats.seconds_texture},
                          {"perturbed_elements", stats.perturbed_elements},
                          {"map_values", stats.map_values}}}};
  return doc.dump() + "\n";
}

}  // namespace bumprad
