#include "server/node.h"

#include "server/directory_store.h"
#include "server/postgres_store.h"

namespace bumprad {

std::unique_ptr<Store> open_store(const NodeOptions& options) {
  if (options.store_url.empty())
    return std::make_unique<DirectoryStore>(options.data_dir, options.store);
  if (options.store_url.starts_with("postgresql://") ||
      options.store_url.starts_with("postgres://"))
    return std::make_unique<PostgresStore>(options.store_url, options.store, options.postgres);
  throw std::runtime_error("--store: \"" + redacted_url(options.store_url) +
                           "\" is not a postgresql:// URL");
}

Node::Node(const NodeOptions& options)
    : store(open_store(options)),
      live(*store),
      solutions(*store, options.cached_solutions, options.api.files),
      runner(*store, metrics, watchdog, options.runner),
      scheduler(options.workers > 0
                    ? std::make_unique<Scheduler>(*store, runner, options.workers, process_name())
                    : nullptr),
      api(*store, live, solutions, metrics, watchdog, options.api,
          std::size_t(std::max(0, options.workers))) {}

}  // namespace bumprad
