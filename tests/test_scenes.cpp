#include "tests/test_scenes.h"

namespace bumprad::test {

Object quad(const std::array<Vec3, 4>& corners, int nu, int nv, int material) {
  Object o;
  o.name = "quad";
  o.shape = QuadShape{corners};
  o.material = material;
  o.density.counts = {nu, nv};
  o.density.patch_elements = 1;
  return o;
}

std::array<Vec3, 4> rectangle_facing_down(double w, double h, double z) {
  return {Vec3(-w / 2, -h / 2, z), Vec3(-w / 2, h / 2, z), Vec3(w / 2, h / 2, z),
          Vec3(w / 2, -h / 2, z)};
}

Scene scene_of(std::vector<Object> objects, double rho, double emission) {
  Scene s;
  Material m;
  m.name = "grey";
  m.reflectance = Rgb(rho);
  m.emission = Rgb(emission);
  s.materials.push_back(m);
  s.objects = std::move(objects);
  return s;
}

}  // namespace bumprad::test
