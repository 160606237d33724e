#pragma once
// Output files of the demos.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

namespace xpbd_demos {

// Writes `j` (pretty-printed) to `file` atomically: the text goes to a
// temporary file in the same directory, which is then renamed over `file`, so
// a reader never sees a half-written file. Creates the directory if needed.
// Throws std::runtime_error naming the path and the reason on failure.
void write_json_atomically(const std::filesystem::path& file, const nlohmann::json& j);

// The same for any text (written byte for byte, no newline added). The
// temporary file is read back and compared before the rename: a write that
// the device or file system swallowed (a full disk) throws, naming `file`.
void write_text_atomically(const std::filesystem::path& file, const std::string& text);

// The whole file as bytes; empty if it cannot be opened.
std::string read_file(const std::filesystem::path& file);

// Creates `dir` if needed and writes and removes a small file in it, so an
// output directory that cannot take the run's files is refused before the
// run. Throws std::runtime_error naming the directory and the reason.
void check_writable_dir(const std::filesystem::path& dir);

// The elements of one JSON array, spooled to a temporary file next to
// `file` as a run produces them (one compact line each), so memory stays
// flat however many there are. write() then puts `head` with the array
// under `key` into `file`: atomically, the close checked and the size
// compared with what was written. The temporary files are removed when the
// spool is destroyed (an interrupted run leaves neither). Errors throw
// std::runtime_error naming `file`.
class JsonArraySpool {
 public:
  explicit JsonArraySpool(std::filesystem::path file);
  ~JsonArraySpool();
  JsonArraySpool(const JsonArraySpool&) = delete;
  JsonArraySpool& operator=(const JsonArraySpool&) = delete;

  void add(const nlohmann::json& element);
  // `head` must be an object without `key`.
  void write(const nlohmann::json& head, const std::string& key);

 private:
  std::filesystem::path file_, spool_;
  std::ofstream out_;
  std::uintmax_t count_ = 0;
};

}  // namespace xpbd_demos
