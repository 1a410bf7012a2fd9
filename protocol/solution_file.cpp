#include "protocol/solution_file.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "common/atomic_file.h"
#include "protocol/scene_json.h"
#include "solver/radiosity/vertex_radiosity.h"

namespace bumprad {
namespace {

constexpr char kMagic[8] = {'B', 'U', 'M', 'P', 'R', 'A', 'D', 'S'};
// Version 2 added the adaptive refinements, 3 the direct part of B, 4 the estimated error
// (solver.tolerance), 5 the map basis (spherical harmonics by default; older files hold
// sampled normals), 6 the rays a pixel a tolerance chose; version 1 files (none) still load.
constexpr std::uint32_t kVersion = 6;
static_assert(std::endian::native == std::endian::little, "the file format is little-endian");

// FNV-1a, 64 bit: enough to tell a damaged file from a whole one.
std::uint64_t fnv1a(const char* data, std::size_t n) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::size_t i = 0; i < n; ++i) h = (h ^ std::uint8_t(data[i])) * 0x100000001b3ull;
  return h;
}

class Writer {
 public:
  template <typename T>
  void put(const T& v) {
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put_rgbs(const std::vector<Rgb>& v) {
    put(std::uint64_t(v.size()));
    for (const Rgb& c : v) put(c);
  }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

class Reader {
 public:
  Reader(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}
  template <typename T>
  T get() {
    T v;
    need(sizeof v);
    std::memcpy(&v, bytes_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  std::vector<Rgb> get_rgbs() {
    std::uint64_t n = get<std::uint64_t>();
    need(n * sizeof(Rgb));
    std::vector<Rgb> v(n);
    std::memcpy(v.data(), bytes_.data() + at_, n * sizeof(Rgb));
    at_ += n * sizeof(Rgb);
    return v;
  }
  std::string get_string() {
    std::uint64_t n = get<std::uint64_t>();
    need(n);
    std::string s(bytes_.substr(at_, n));
    at_ += n;
    return s;
  }

 private:
  void need(std::uint64_t n) const {
    if (n > bytes_.size() - at_) throw SolutionFileError(name_ + ": truncated solution file");
  }
  std::string_view bytes_;
  std::size_t at_ = 0;
  std::string name_;
};

}  // namespace

void save_solution(const std::filesystem::path& path, std::string_view scene_json,
                   const Solution& solution) {
  write_file_atomically(path, encode_solution(scene_json, solution));
}

std::string encode_solution(std::string_view scene_json, const Solution& solution) {
  Writer w;
  w.bytes().append(kMagic, sizeof kMagic);
  w.put(kVersion);
  w.put(std::uint64_t(scene_json.size()));
  w.bytes().append(scene_json);
  w.put_rgbs(solution.radiosity);
  w.put_rgbs(solution.display);
  std::vector<Rgb> map;
  if (solution.map)
    for (std::uint32_t slot = 0; slot < solution.map->vertex_count(); ++slot)
      for (const Rgb& b : solution.map->values(slot)) map.push_back(b);
  w.put_rgbs(map);
  const SolveStats& s = solution.stats;
  w.put(std::int64_t(s.shots));
  w.put(s.seconds_solve);
  w.put(s.unshot_fraction);
  w.put(s.seconds_texture);
  w.put(std::uint64_t(solution.refinements.size()));
  for (const auto& split : solution.refinements) {
    w.put(std::uint64_t(split.size()));
    for (std::uint32_t i : split) w.put(i);
  }
  w.put_rgbs(solution.direct);
  w.put(s.estimated_error);
  w.put(s.estimated_error_se);
  w.put(std::int32_t(s.antialias));
  w.put(fnv1a(w.bytes().data(), w.bytes().size()));
  return std::move(w.bytes());
}

LoadedSolution load_solution(const std::filesystem::path& path, const ImageFiles& files) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SolutionFileError(path.string() + ": cannot open the solution file");
  std::ostringstream text;
  text << in.rdbuf();
  return decode_solution(text.str(), path.string(), files);
}

LoadedSolution decode_solution(std::string_view bytes, const std::string& name,
                               const ImageFiles& files) {
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw SolutionFileError(name + ": not a bumprad solution file");
  Reader header(std::string_view(bytes).substr(sizeof kMagic), name);
  std::uint32_t version = header.get<std::uint32_t>();
  if (version > kVersion || version < 1)
    throw SolutionFileError(name + ": solution file format version " + std::to_string(version) +
                            "; this build reads versions 1 to " + std::to_string(kVersion));
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  std::uint64_t stored;
  if (bytes.size() < sizeof kMagic + sizeof version + sizeof stored)
    throw SolutionFileError(name + ": truncated solution file");
  std::memcpy(&stored, bytes.data() + body, sizeof stored);
  if (stored != fnv1a(bytes.data(), body))
    throw SolutionFileError(name + ": corrupt or truncated solution file (checksum mismatch)");

  Reader r(std::string_view(bytes).substr(sizeof kMagic + sizeof version, body), name);
  LoadedSolution out;
  out.scene_json = r.get_string();
  try {
    out.scene = parse_scene(std::string_view(out.scene_json), files);
  } catch (const SceneError& e) {
    throw SolutionFileError(name + ": its scene is invalid: " + e.what());
  }
  if (version < 5) out.scene.solver.map.basis = MapBasisKind::SampledNormals;
  Solution& s = out.solution;
  s.radiosity = r.get_rgbs();
  s.display = r.get_rgbs();
  std::vector<Rgb> map = r.get_rgbs();
  s.stats.shots = int(r.get<std::int64_t>());
  s.stats.seconds_solve = r.get<double>();
  s.stats.unshot_fraction = r.get<double>();
  s.stats.seconds_texture = r.get<double>();
  if (version >= 2) {
    std::uint64_t levels = r.get<std::uint64_t>();
    if (levels > 16) throw SolutionFileError(name + ": implausible refinement levels");
    s.refinements.resize(levels);
    for (auto& split : s.refinements) {
      std::uint64_t n = r.get<std::uint64_t>();
      if (n > std::uint64_t(Limits::kMaxElements))
        throw SolutionFileError(name + ": implausible refinement size");
      split.resize(n);
      for (std::uint32_t& i : split) i = r.get<std::uint32_t>();
    }
  }
  // Version 3: the direct part of B (exact direct light). Older files hold all light in
  // the radiosity and the map, and render so.
  if (version >= 3) s.direct = r.get_rgbs();
  if (version >= 4) {
    s.stats.estimated_error = r.get<double>();
    s.stats.estimated_error_se = r.get<double>();
  }
  if (version >= 6) {
    s.stats.antialias = r.get<std::int32_t>();
    if (s.stats.antialias < 0 || s.stats.antialias > Limits::kMaxAntialias)
      throw SolutionFileError(name + ": implausible rays a pixel");
  }
  try {
    s.mesh = refined_mesh(out.scene, s.refinements);
  } catch (const std::invalid_argument& e) {
    throw SolutionFileError(name + ": its refinements do not fit its scene's mesh: " + e.what());
  }
  s.map = make_map(out.scene, *s.mesh);
  const std::size_t values = s.map ? s.map->vertex_count() * s.map->basis().size() : 0;
  if (s.radiosity.size() != s.mesh->elements.size() || s.display.size() != s.radiosity.size() ||
      map.size() != values || (!s.direct.empty() && s.direct.size() != s.radiosity.size()))
    throw SolutionFileError(name + ": its data does not fit its scene's mesh");
  if (s.map) {
    const std::size_t n = s.map->basis().size();
    for (std::uint32_t slot = 0; slot < s.map->vertex_count(); ++slot)
      std::copy_n(map.begin() + std::ptrdiff_t(slot * n), n, s.map->values(slot).begin());
  }
  s.stats.elements = s.mesh->elements.size();
  count_map_stats(out.scene, s);
  s.rays = std::make_unique<RayScene>(*s.mesh);
  s.open = open_parts(*s.mesh, *s.rays);
  if (!s.direct.empty()) s.near = std::make_unique<NearField>(*s.mesh, *s.rays, s.open.share);
  return out;
}

}  // namespace bumprad
