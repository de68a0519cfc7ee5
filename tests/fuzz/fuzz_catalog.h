#pragma once
// What the service fuzz targets check requests against: a catalog of the
// bundled robot and scenes, the hand map seed and one object database seed
// (registered under the names of the scenes' targets), so that no
// preprocessing is needed.

#include <filesystem>
#include <memory>
#include <string>

#include "service/planning_catalog.h"

namespace hfts::fuzz {

/// `relative` inside the source tree.
std::filesystem::path sourcePath(const std::string& relative);

/// Built on first use (about a second), then shared.
std::shared_ptr<const service::PlanningCatalog> catalog();

/// Aborts with `what` on stderr: a broken promise of the code under test
/// that is no crash by itself (libFuzzer then keeps the input).
[[noreturn]] void contractViolated(const std::string& what);

}  // namespace hfts::fuzz
