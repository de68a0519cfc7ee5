#include "core/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

#include "test_meshes.h"

namespace hfts::core {
namespace {

using test::TempDir;

TEST(AtomicFile, WritesAndReplaces) {
  TempDir dir;
  writeFileAtomically(dir / "f.txt", "one");
  writeFileAtomically(dir / "f.txt", "two");
  EXPECT_EQ(test::readBytes(dir / "f.txt"), "two");
  EXPECT_THROW(writeFileAtomically(dir / "missing" / "f.txt", "x"), std::runtime_error);
}

TEST(AtomicFile, LeavesNoTemporaryFileBehind) {
  TempDir dir;
  writeFileAtomically(dir / "f.txt", "content");
  EXPECT_THROW(writeFileAtomically(dir / "missing" / "f.txt", "x"), std::runtime_error);
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path()))
    ++files;
  EXPECT_EQ(files, 1);
}

TEST(AtomicFile, TemporarySiblingsAreNextToThePathAndDiffer) {
  const std::filesystem::path path = "/some/dir/plan.json";
  const std::filesystem::path a = temporarySibling(path), b = temporarySibling(path);
  EXPECT_EQ(a.parent_path(), path.parent_path());
  EXPECT_NE(a, b);
  EXPECT_NE(a, path);
}

}  // namespace
}  // namespace hfts::core
