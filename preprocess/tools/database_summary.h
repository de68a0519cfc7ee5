#pragma once
// What `hfts-preprocess --inspect` prints.

#include <nlohmann/json.hpp>

#include <string>

#include "graspability_report.h"
#include "hfts_db/object_database.h"

namespace hfts::preprocess {

/// Machine-readable summary (keys documented in docs/database.md).
nlohmann::json databaseSummaryJson(const db::ObjectDatabase& db,
                                   const GraspabilityReport& graspability);

/// The same summary for a person.
std::string databaseSummaryText(const db::ObjectDatabase& db,
                                const GraspabilityReport& graspability);

}  // namespace hfts::preprocess
