#pragma once
// Fuzz inputs as files, for the loaders that read paths: one scratch file
// per process (libFuzzer's -jobs run several), removed at exit.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace hfts::fuzz {

class ScratchFile {
 public:
  /// `<temp dir>/hfts_fuzz_<pid>_<stem><extension>`.
  ScratchFile(const std::string& stem, const std::string& extension)
      : path_(std::filesystem::temp_directory_path() /
              ("hfts_fuzz_" + std::to_string(::getpid()) + "_" + stem + extension)) {}
  ~ScratchFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  /// Replaces the file's content with `size` bytes at `data`.
  const std::filesystem::path& write(const std::uint8_t* data, std::size_t size) {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    return path_;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace hfts::fuzz
