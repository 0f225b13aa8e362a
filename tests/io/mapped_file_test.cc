// A mapped input that another program truncates while it is read: an error naming the file, not
// a SIGBUS that ends the process (engine/io/mapped_file.h).
#include "engine/io/mapped_file.h"

#include <unistd.h>

#include <string>

#include "gtest/gtest.h"
#include "tests/support/files.h"

namespace femsimp {
namespace {

class MappedFileTest : public testing::TempDirTest {};

uint64_t Sum(absl::string_view bytes) {
  uint64_t sum = 0;
  for (char c : bytes) sum += static_cast<unsigned char>(c);
  return sum;
}

TEST_F(MappedFileTest, FileShrunkUnderTheMappingIsAnError) {
  const std::string contents(1 << 20, '\x5');
  const std::string path = Write("big.stl", contents);
  absl::StatusOr<MappedFile> file = MappedFile::Open(path);
  ASSERT_TRUE(file.ok()) << file.status();
  uint64_t sum = 0;
  ASSERT_TRUE(file->Read([&](absl::string_view bytes) { sum = Sum(bytes); }).ok());
  EXPECT_EQ(sum, 5u << 20);

  ASSERT_EQ(::truncate(path.c_str(), 4096), 0);  // the pages past the first are gone
  sum = 0;
  const absl::Status shrunk = file->Read([&](absl::string_view bytes) { sum = Sum(bytes); });
  EXPECT_EQ(shrunk.code(), absl::StatusCode::kFailedPrecondition) << shrunk;
  EXPECT_NE(shrunk.message().find(path), std::string::npos) << shrunk;
  EXPECT_NE(shrunk.message().find("shrank while it was read (1048576 bytes when opened, 4096 now)"),
            std::string::npos)
      << shrunk;
  EXPECT_EQ(sum, 0u) << "the read was abandoned, not finished";

  // The process goes on, and reads the file as it is now.
  absl::StatusOr<MappedFile> again = MappedFile::Open(path);
  ASSERT_TRUE(again.ok()) << again.status();
  ASSERT_TRUE(again->Read([&](absl::string_view bytes) { sum = Sum(bytes); }).ok());
  EXPECT_EQ(sum, 5u * 4096);
}

}  // namespace
}  // namespace femsimp
