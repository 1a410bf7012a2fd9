// The PostgreSQL schema's migrations (server/migrations/NNN_name.sql), compiled in: the
// i-th brings the schema from version i to i + 1. postgres_store.cpp applies those a
// database lacks, at start.
#pragma once

#include <span>
#include <string_view>

namespace bumprad {

std::span<const std::string_view> schema_migrations();

}  // namespace bumprad
