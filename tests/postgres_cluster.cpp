#include "tests/postgres_cluster.h"

#include <unistd.h>

#include <cstdlib>
#include <stdexcept>

#include "tests/test_command.h"

namespace bumprad::test {
namespace {

constexpr int kPort = 5432;  // on a socket in our own directory: no clash with a real one

std::string postgres_bin() {
  std::filesystem::path newest;
  std::error_code ignored;
  for (const auto& entry : std::filesystem::directory_iterator("/usr/lib/postgresql", ignored))
    if (std::filesystem::exists(entry.path() / "bin" / "initdb") && entry.path() > newest)
      newest = entry.path();
  if (newest.empty())
    throw std::runtime_error(
        "PostgreSQL is not installed (/usr/lib/postgresql/*/bin/initdb); scripts/setup.sh "
        "--tests installs it");
  return (newest / "bin").string();
}

}  // namespace

PostgresCluster::PostgresCluster() : bin_(postgres_bin()), root_(::geteuid() == 0) {
  // Short: the socket's path must fit in 107 bytes.
  char templ[] = "/tmp/bumprad-pg-XXXXXX";
  if (!::mkdtemp(templ)) throw std::runtime_error("cannot make a directory for PostgreSQL");
  dir_ = templ;
  if (root_ && run_command("chown postgres: " + dir_.string()).exit_code != 0)
    throw std::runtime_error("cannot give " + dir_.string() + " to the postgres user");
  auto init = run_command(as_owner(bin_ + "/initdb -D " + dir_.string() +
                                   "/data -A trust -U bumprad --no-sync -E UTF8"));
  if (init.exit_code != 0) throw std::runtime_error("initdb failed: " + init.output);
  start();
}

void PostgresCluster::start() {
  auto started = run_command(
      as_owner(bin_ + "/pg_ctl -D " + dir_.string() + "/data -l " + dir_.string() +
               "/log -w start -o \"" + "-c listen_addresses='' -k " + dir_.string() + " -p " +
               std::to_string(kPort) + " -c fsync=off -c max_connections=200\""));
  if (started.exit_code != 0) throw std::runtime_error("pg_ctl start failed: " + started.output);
}

void PostgresCluster::stop() {
  run_command(as_owner(bin_ + "/pg_ctl -D " + dir_.string() + "/data -m immediate -w stop"));
}

PostgresCluster::~PostgresCluster() {
  stop();
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

std::string PostgresCluster::as_owner(const std::string& command) const {
  return root_ ? "runuser -u postgres -- " + command : command;
}

std::string PostgresCluster::create_database(const std::string& name) {
  auto made = run_command(bin_ + "/createdb -h " + dir_.string() + " -p " + std::to_string(kPort) +
                          " -U bumprad " + name);
  if (made.exit_code != 0) throw std::runtime_error("createdb failed: " + made.output);
  return "postgresql:///" + name + "?host=" + dir_.string() + "&port=" + std::to_string(kPort) +
         "&user=bumprad";
}

}  // namespace bumprad::test
