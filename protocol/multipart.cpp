#include "protocol/multipart.h"

#include <algorithm>
#include <cctype>

namespace bumprad {
namespace {

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// The `name` parameter of a header value ("form-data; name=\"a\"; filename=\"b.png\""):
// token or quoted string (backslash escapes the next character).
std::string header_parameter(std::string_view value, std::string_view name) {
  std::size_t at = value.find(';');
  while (at != std::string_view::npos) {
    std::string_view rest = trim(value.substr(at + 1));
    const std::size_t eq = rest.find('=');
    if (eq == std::string_view::npos) return {};
    const std::string_view key = trim(rest.substr(0, eq));
    rest = trim(rest.substr(eq + 1));
    std::string out;
    std::size_t end = 0;
    if (!rest.empty() && rest.front() == '"') {
      for (end = 1; end < rest.size() && rest[end] != '"'; ++end) {
        if (rest[end] == '\\' && end + 1 < rest.size()) ++end;
        out += rest[end];
      }
      ++end;
    } else {
      end = std::min(rest.find(';'), rest.size());
      out = std::string(trim(rest.substr(0, end)));
    }
    if (iequals(key, name)) return out;
    const std::size_t next = rest.find(';', std::min(end, rest.size()));
    if (next == std::string_view::npos) return {};
    at = std::size_t(rest.data() + next - value.data());
  }
  return {};
}

}  // namespace

std::string media_type_parameter(std::string_view content_type, std::string_view name) {
  return header_parameter(content_type, name);
}

std::vector<FormPart> parse_multipart(std::string_view content_type, std::string_view body) {
  const std::string boundary = media_type_parameter(content_type, "boundary");
  if (boundary.empty() || boundary.size() > 70)
    throw MalformedBody("multipart/form-data needs a boundary of 1 to 70 characters");
  const std::string delimiter = "--" + boundary;
  std::size_t at = body.find(delimiter);
  if (at == std::string_view::npos)
    throw MalformedBody("the form's boundary never appears in the body");
  std::vector<FormPart> parts;
  for (;;) {
    at += delimiter.size();
    if (body.substr(at, 2) == "--") return parts;  // the close delimiter
    if (body.substr(at, 2) != "\r\n")
      throw MalformedBody("part " + std::to_string(parts.size() + 1) +
                          ": a boundary must end its line");
    at += 2;
    const std::size_t headers_end = body.find("\r\n\r\n", at);
    const std::size_t next = body.find("\r\n" + delimiter, at);
    if (next == std::string_view::npos)
      throw MalformedBody("part " + std::to_string(parts.size() + 1) +
                          " never ends (the closing boundary is missing)");
    if (headers_end == std::string_view::npos || headers_end > next)
      throw MalformedBody("part " + std::to_string(parts.size() + 1) +
                          ": needs Content-Disposition: form-data with a name");
    FormPart part;
    bool form_data = false;
    const std::string_view headers = body.substr(at, headers_end - at);
    for (std::size_t line = 0; line < headers.size();) {
      const std::size_t eol = std::min(headers.find("\r\n", line), headers.size());
      const std::string_view h = headers.substr(line, eol - line);
      line = eol + 2;
      const std::size_t colon = h.find(':');
      if (colon == std::string_view::npos)
        throw MalformedBody("part " + std::to_string(parts.size() + 1) +
                            ": a header line without a colon");
      if (!iequals(trim(h.substr(0, colon)), "content-disposition")) continue;
      const std::string_view value = trim(h.substr(colon + 1));
      form_data = iequals(trim(value.substr(0, value.find(';'))), "form-data");
      part.name = header_parameter(value, "name");
      part.filename = header_parameter(value, "filename");
    }
    if (!form_data || part.name.empty())
      throw MalformedBody("part " + std::to_string(parts.size() + 1) +
                          ": needs Content-Disposition: form-data with a name");
    const std::size_t content = headers_end + 4;
    part.body = body.substr(content, next - content);
    parts.push_back(std::move(part));
    at = next + 2;
  }
}

}  // namespace bumprad
