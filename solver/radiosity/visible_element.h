// What every form-factor method gives for a shot: the elements it reaches, each with its
// form factor from the shooter.
#pragma once

#include <cstdint>

namespace bumprad {

struct VisibleElement {
  std::uint32_t element;
  double form_factor;
};

}  // namespace bumprad
