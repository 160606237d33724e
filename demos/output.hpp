#pragma once
// Output files of the demos.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace xpbd_demos {

// Writes `j` (pretty-printed) to `file` atomically: the text goes to a
// temporary file in the same directory, which is then renamed over `file`, so
// a reader never sees a half-written file. Creates the directory if needed.
// Throws std::runtime_error naming the path and the reason on failure.
void write_json_atomically(const std::filesystem::path& file, const nlohmann::json& j);

// The same for any text (written byte for byte, no newline added).
void write_text_atomically(const std::filesystem::path& file, const std::string& text);

}  // namespace xpbd_demos
