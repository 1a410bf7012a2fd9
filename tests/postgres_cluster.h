// A throw-away PostgreSQL for the tests: a cluster initialised in a temporary directory
// (Debian's postgresql package, installed by scripts/setup.sh --tests), listening only on a
// Unix socket there, stopped and removed when the object goes. As root it runs as the
// `postgres` user, since PostgreSQL refuses to run as root.
#pragma once

#include <filesystem>
#include <string>

namespace bumprad::test {

class PostgresCluster {
 public:
  // Throws std::runtime_error with initdb's or pg_ctl's output when it cannot start.
  PostgresCluster();
  ~PostgresCluster();
  PostgresCluster(const PostgresCluster&) = delete;
  PostgresCluster& operator=(const PostgresCluster&) = delete;

  // A new, empty database; its URL.
  std::string create_database(const std::string& name);

  // An outage: the server stops at once (connections cut) and starts again, the data kept.
  void stop();
  void start();

 private:
  std::string as_owner(const std::string& command) const;
  std::filesystem::path dir_;
  std::string bin_;
  bool root_;
};

}  // namespace bumprad::test
