#pragma once

#include <filesystem>
#include <string_view>

namespace hfts::core {

/// Writes `content` to a temporary file next to `path`, flushes it and
/// renames it over `path`, so readers see the old file or the complete new
/// one, never a partial one. Throws std::runtime_error naming the file.
void writeFileAtomically(const std::filesystem::path& path, std::string_view content);

/// A temporary name next to `path`, unique within this process.
std::filesystem::path temporarySibling(const std::filesystem::path& path);

}  // namespace hfts::core
