// Job submissions that carry their files: a bare glTF binary (model/gltf-binary), or a form
// (multipart/form-data) of the job or scene JSON and the files it names. Both become the
// one JSON job request (api_json.h), the files inside its scene's "files", so the stored
// job holds everything it needs in either store.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "protocol/multipart.h"

namespace bumprad {

// The Content-Type is not one a job takes (HTTP 415).
class UnsupportedMediaType : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The JSON job request for a body of this Content-Type: application/json (or none) as it is;
// model/gltf-binary as the scene of that one model ("model.glb"), its own camera or one
// framed on it; multipart/form-data with a part "job" (a job request) or "scene" (a scene),
// every other part a file under its filename. Throws UnsupportedMediaType, MalformedBody,
// and SceneError (a form's JSON is not JSON, or it names files without an inline scene).
std::string job_request_json(std::string_view content_type, std::string_view body);

}  // namespace bumprad
