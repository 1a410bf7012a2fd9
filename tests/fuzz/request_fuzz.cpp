// libFuzzer target for everything that reads JSON from a client or a data directory: job
// and re-texture requests, scenes, job records and step events, and the problem details
// that quote them. Built with AddressSanitizer and UBSan by scripts/fuzz.sh. A parser may
// only ever throw SceneError (MalformedJson included): any other exception, crash, leak or
// undefined behaviour is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "protocol/api_json.h"
#include "protocol/builtin_scenes.h"
#include "protocol/scene_json.h"

namespace {

const bumprad::Scene& solved_scene() {
  static const bumprad::Scene scene =
      bumprad::parse_scene(*bumprad::find_builtin_scene("wrinkled-box"));
  return scene;
}

template <typename F>
void expect_only_scene_errors(F&& parse) {
  try {
    parse();
  } catch (const bumprad::SceneError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto files = bumprad::ImageFiles::refused();
  expect_only_scene_errors([&] { bumprad::parse_job_request(text, files); });
  expect_only_scene_errors([&] { bumprad::parse_retexture_request(text, solved_scene(), files); });
  expect_only_scene_errors([&] { bumprad::parse_scene(text, files); });
  expect_only_scene_errors([&] { bumprad::job_from_json(text); });
  expect_only_scene_errors([&] { bumprad::step_event_from_json(text); });
  bumprad::problem_json(422, "Invalid request", text, text);
  return 0;
}
