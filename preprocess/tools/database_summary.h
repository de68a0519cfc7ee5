#pragma once
// What `hfts-preprocess --inspect` prints.

#include <nlohmann/json.hpp>

#include <string>

#include "hfts_db/object_database.h"

namespace hfts::preprocess {

/// Machine-readable summary (keys documented in docs/database.md).
nlohmann::json databaseSummaryJson(const db::ObjectDatabase& db);

/// The same summary for a person.
std::string databaseSummaryText(const db::ObjectDatabase& db);

}  // namespace hfts::preprocess
