#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "util/atomic_file.h"
#include "util/error.h"
#include "util/interval.h"
#include "util/sha256.h"

namespace cdbench {
namespace {

std::string read_all(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string temp_dir() {
  auto dir = std::filesystem::temp_directory_path() / ("cdbench_util_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

TEST(AtomicFile, WritesAndReplaces) {
  const std::string path = temp_dir() + "/a.txt";
  write_file_atomically(path, [](std::ostream& o) { o << "first"; });
  EXPECT_EQ(read_all(path), "first");
  write_file_atomically(path, [](std::ostream& o) { o << "second"; });
  EXPECT_EQ(read_all(path), "second");
}

TEST(AtomicFile, FailureLeavesTargetAndNoTemporary) {
  const std::string dir = temp_dir();
  const std::string path = dir + "/b.txt";
  write_file_atomically(path, [](std::ostream& o) { o << "kept"; });
  EXPECT_THROW(write_file_atomically(path,
                                     [](std::ostream& o) {
                                       o << "partial";
                                       throw std::runtime_error("interrupted");
                                     }),
               std::runtime_error);
  EXPECT_EQ(read_all(path), "kept");
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

TEST(AtomicFile, MissingDirectoryIsAnInputError) {
  EXPECT_THROW(write_file_atomically("/nonexistent-dir/x.txt", [](std::ostream& o) { o << "x"; }), InputError);
}

TEST(Interval, OutwardRoundingMovesOneUlp) {
  EXPECT_GT(round_up(1.0), 1.0);
  EXPECT_LT(round_down(1.0), 1.0);
  EXPECT_EQ(round_up(round_down(1.0)), 1.0);
  const Interval i{1.0, 3.0};
  EXPECT_TRUE(i.contains(2.0));
  EXPECT_FALSE(i.contains(3.5));
  EXPECT_DOUBLE_EQ(i.width(), 2.0);
}

TEST(Sha256, KnownVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const std::string path = temp_dir() + "/h.txt";
  write_file_atomically(path, [](std::ostream& o) { o << "abc"; });
  EXPECT_EQ(sha256_file(path), sha256_hex("abc"));
  EXPECT_THROW(sha256_file("/nonexistent/file"), InputError);
}

}  // namespace
}  // namespace cdbench
