// multipart/form-data bodies (RFC 7578): the parts of a form a browser or curl -F sends, each
// with its field name, its file name when it is a file, and its bytes.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace bumprad {

// The body is not the form its Content-Type says (HTTP 400); the message says where.
class MalformedBody : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct FormPart {
  std::string name;       // Content-Disposition's name
  std::string filename;   // its filename; empty for a plain field
  std::string_view body;  // into the body given to parse_multipart
};

// A media type's parameter (`boundary` of "multipart/form-data; boundary=x"), unquoted;
// empty when it has none.
std::string media_type_parameter(std::string_view content_type, std::string_view name);

// The parts of `body`, split at the boundary `content_type` names. Throws MalformedBody.
std::vector<FormPart> parse_multipart(std::string_view content_type, std::string_view body);

}  // namespace bumprad
