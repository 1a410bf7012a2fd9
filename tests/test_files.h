// Real files for the tests: a fresh, empty directory per test.
#pragma once

#include <filesystem>
#include <string>

namespace bumprad::test {

// <tmp>/bumprad-<prefix>-<current test name>, emptied and created (and the log a test
// server kept beside it, DIR.log, removed).
std::filesystem::path fresh_temp_dir(const std::string& prefix);

// The whole file; throws std::runtime_error when it cannot be read.
std::string read_file(const std::filesystem::path& path);
void write_file(const std::filesystem::path& path, const std::string& bytes);

// A 68-byte PNG whose header says 20000 x 20000 pixels (an image bomb): readers must refuse
// it from the header, before decoding.
std::string png_bomb();

// Debian's assimp-testmodels (scripts/test-packages.txt): real model files.
inline const std::filesystem::path kTestModels = "/usr/share/assimp/models";

}  // namespace bumprad::test
