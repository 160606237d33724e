// Output files that cannot lie (demos/output.hpp): a text written, or an
// array spooled (JsonArraySpool), to a full disk is an error naming the
// file, never a file listed as written, and an output directory that
// cannot take files is refused before a run.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstddef>
#include <filesystem>
#include <iterator>
#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "demos/output.hpp"

namespace xpbd_demos {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

namespace fs = std::filesystem;

class Output : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("xpbd_output_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::string what_of(const auto& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST_F(Output, TextReadsBackAsWritten) {
  const fs::path f = dir_ / "metrics.json";
  const std::string text = "{\"a\": 1}\n";
  write_text_atomically(f, text);
  EXPECT_EQ(read_file(f), text);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);  // no temporary left
}

// A full disk for this one file: its temporary (next to the target, named
// with this process's id) is a link to /dev/full, where every write fails
// with ENOSPC. The old target stays as it was.
TEST_F(Output, TextOnAFullDiskIsAnErrorNamingTheFile) {
  ASSERT_TRUE(fs::exists("/dev/full"));
  const fs::path f = dir_ / "metrics.json";
  write_text_atomically(f, "old\n");
  fs::create_symlink("/dev/full", dir_ / (".metrics.json.tmp." + std::to_string(::getpid())));
  const std::string msg = what_of([&] { write_text_atomically(f, std::string(100000, 'x')); });
  EXPECT_NE(msg.find(f.string()), std::string::npos) << msg;
  EXPECT_EQ(read_file(f), "old\n");
}

// A spooled array comes out as the last member of its object, every
// element in order, and the spool leaves no temporary file behind.
TEST_F(Output, SpooledArrayIsTheLastMemberWithEveryElement) {
  const fs::path f = dir_ / "metrics.json";
  {
    JsonArraySpool spool(f);
    for (int k = 0; k < 5; ++k) spool.add({{"frame", k}, {"x", 0.5 * k}});
    spool.write({{"scene", "s"}, {"frames", 5}}, "per_frame");
  }
  const nlohmann::json j = nlohmann::json::parse(read_file(f));
  EXPECT_EQ(j["scene"], "s");
  ASSERT_EQ(j["per_frame"].size(), 5u);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(j["per_frame"][std::size_t(k)]["frame"], k);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
  // Empty array, empty head.
  {
    JsonArraySpool spool(f);
    spool.write(nlohmann::json::object(), "per_frame");
  }
  EXPECT_EQ(nlohmann::json::parse(read_file(f)), nlohmann::json({{"per_frame", nlohmann::json::array()}}));
  // A run that stops before write() (interrupted) leaves neither file.
  { JsonArraySpool spool(dir_ / "other.json"); spool.add(1); }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

// The same full disk for a spooled file: an error naming it, the old file
// kept.
TEST_F(Output, SpooledFileOnAFullDiskIsAnErrorNamingIt) {
  ASSERT_TRUE(fs::exists("/dev/full"));
  const fs::path f = dir_ / "metrics.json";
  write_text_atomically(f, "old\n");
  fs::create_symlink("/dev/full", dir_ / (".metrics.json.tmp." + std::to_string(::getpid())));
  JsonArraySpool spool(f);
  for (int k = 0; k < 1000; ++k) spool.add({{"frame", k}});
  const std::string msg = what_of([&] { spool.write({{"a", 1}}, "per_frame"); });
  EXPECT_NE(msg.find(f.string()), std::string::npos) << msg;
  EXPECT_EQ(read_file(f), "old\n");
}

// An output directory below a regular file cannot be created; one that is
// a file is not a directory. Both are named.
TEST_F(Output, UnwritableDirectoryIsRefusedNamingIt) {
  const fs::path file = dir_ / "plain";
  { std::ofstream(file) << "x"; }
  std::string msg = what_of([&] { check_writable_dir(file / "out"); });
  EXPECT_NE(msg.find((file / "out").string()), std::string::npos) << msg;
  msg = what_of([&] { check_writable_dir(file); });
  EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
  // A good one is created and left empty.
  EXPECT_EQ(what_of([&] { check_writable_dir(dir_ / "a" / "b"); }), "");
  EXPECT_TRUE(fs::is_directory(dir_ / "a" / "b"));
  EXPECT_TRUE(fs::is_empty(dir_ / "a" / "b"));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_demos
