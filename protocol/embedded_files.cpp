#include "protocol/embedded_files.h"

#include <cstdlib>
#include <fstream>
#include <system_error>

#include "protocol/base64.h"
#include "protocol/json_node.h"

namespace bumprad {
namespace {

constexpr std::size_t kMaxFiles = 1000;
constexpr std::size_t kMaxNameLength = 255;

// Why `name` cannot name an embedded file, or empty when it can.
std::string name_problem(const std::string& name) {
  if (name.empty() || name.size() > kMaxNameLength)
    return "a file name must be 1 to " + std::to_string(kMaxNameLength) + " characters";
  if (name.front() == '/' || name.back() == '/')
    return "a file name must be a relative path that names a file";
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t end = std::min(name.find('/', start), name.size());
    const std::string part = name.substr(start, end - start);
    if (part.empty() || part == "." || part == "..")
      return "a file name must be a relative path without empty, \".\" or \"..\" parts";
    for (unsigned char c : part)
      if (c < 0x20 || c == 0x7f || c == '\\' || c == ':')
        return "a file name must not hold control characters, \"\\\" or \":\"";
    start = end + 1;
  }
  return {};
}

}  // namespace

EmbeddedFiles::EmbeddedFiles(const nlohmann::json& value, const std::string& pointer) {
  const Node files(value, pointer);
  const nlohmann::json& object = files.object();
  if (object.size() > kMaxFiles)
    files.fail("at most " + std::to_string(kMaxFiles) + " files (got " +
               std::to_string(object.size()) + ")");
  std::string pattern = (std::filesystem::temp_directory_path() / "bumprad-files-XXXXXX").string();
  if (!mkdtemp(pattern.data()))
    throw std::runtime_error("cannot make a temporary directory for a scene's files");
  dir_ = pattern;
  try {
    for (auto it = object.begin(); it != object.end(); ++it) {
      const Node entry(*it, files.pointer() + "/" + escape_token(it.key()));
      if (const std::string why = name_problem(it.key()); !why.empty()) entry.fail(why);
      const auto bytes = base64_decode(entry.string());
      if (!bytes) entry.fail("must be the file's bytes in base64 (RFC 4648, padded)");
      const std::filesystem::path file = dir_ / it.key();
      std::error_code error;
      std::filesystem::create_directories(file.parent_path(), error);
      if (error || std::filesystem::exists(file))
        entry.fail("its name clashes with another file's (a file cannot also be a folder)");
      std::ofstream out(file, std::ios::binary);
      out.write(bytes->data(), std::streamsize(bytes->size()));
      if (!out.flush())
        throw std::runtime_error("cannot write a scene's file to the temporary directory");
      names_.insert(it.key());
    }
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
    throw;
  }
}

EmbeddedFiles::~EmbeddedFiles() {
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

}  // namespace bumprad
