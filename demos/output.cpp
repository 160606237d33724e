#include "demos/output.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <unistd.h>

namespace xpbd_demos {

namespace fs = std::filesystem;

std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void check_writable_dir(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("output directory '" + dir.string() + "': cannot create it: " + ec.message());
  const fs::path probe = dir / ".xpbd-write-probe";
  write_text_atomically(probe, "probe\n");
  fs::remove(probe, ec);
  if (ec) throw std::runtime_error("output directory '" + dir.string() + "': cannot remove '" + probe.string() + "': " + ec.message());
}

void write_json_atomically(const fs::path& file, const nlohmann::json& j) {
  // Non-finite numbers become null (nlohmann's dump); no exception for
  // invalid UTF-8 since all strings are ours.
  write_text_atomically(file, j.dump(2) + '\n');
}

void write_text_atomically(const fs::path& file, const std::string& text) {
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create directory '" + dir.string() + "': " + ec.message());

  // Same directory as the target, so the rename cannot cross file systems.
  // The process id keeps two concurrent writers apart.
  // (Built with += : GCC 12 warns falsely, -Wrestrict, on "literal" + std::string&&.)
  std::string tmp_name = ".";
  tmp_name += file.filename().string();
  tmp_name += ".tmp.";
  tmp_name += std::to_string(::getpid());
  const fs::path tmp = dir / tmp_name;
  auto fail = [&](const std::string& why) {
    std::error_code ignore;
    fs::remove(tmp, ignore);
    throw std::runtime_error(why);
  };
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) fail("cannot open '" + tmp.string() + "' for writing (for '" + file.string() + "')");
    out << text;
    out.close();  // a full disk can show only here
    if (!out) fail("cannot write '" + file.string() + "' (temporary '" + tmp.string() + "')");
  }
  // Read back before it replaces the target: a device that swallowed the
  // bytes, or a file system that kept fewer of them, is an error here, not
  // a file listed as written.
  if (!fs::is_regular_file(tmp, ec) || read_file(tmp) != text)
    fail("'" + file.string() + "' did not read back as written (temporary '" + tmp.string() + "')");
  fs::rename(tmp, file, ec);
  if (ec) {
    std::error_code ignore;
    fs::remove(tmp, ignore);
    throw std::runtime_error("cannot rename '" + tmp.string() + "' to '" + file.string() +
                             "': " + ec.message());
  }
}

namespace {

fs::path temporary_next_to(const fs::path& file, const char* kind) {
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::string name = ".";
  name += file.filename().string();
  name += kind;
  name += std::to_string(::getpid());
  return dir / name;
}

}  // namespace

JsonArraySpool::JsonArraySpool(fs::path file) : file_(std::move(file)), spool_(temporary_next_to(file_, ".spool.")) {
  const fs::path dir = file_.has_parent_path() ? file_.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create directory '" + dir.string() + "': " + ec.message());
  out_.open(spool_, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot open '" + spool_.string() + "' for writing (for '" + file_.string() + "')");
}

JsonArraySpool::~JsonArraySpool() {
  out_.close();
  std::error_code ignore;
  fs::remove(spool_, ignore);
}

void JsonArraySpool::add(const nlohmann::json& element) {
  out_ << element.dump() << '\n';
  if (!out_) throw std::runtime_error("cannot write '" + file_.string() + "' (temporary '" + spool_.string() + "')");
  ++count_;
}

void JsonArraySpool::write(const nlohmann::json& head, const std::string& key) {
  out_.close();
  if (!out_) throw std::runtime_error("cannot write '" + file_.string() + "' (temporary '" + spool_.string() + "')");
  if (!head.is_object() || head.contains(key))
    throw std::invalid_argument("JsonArraySpool::write: head must be an object without '" + key + "'");
  // head.dump(2) is "{\n  ...\n}" (or "{}"): the array goes in as its last member.
  std::string prefix = head.dump(2);
  prefix.pop_back();  // '}'
  while (!prefix.empty() && (prefix.back() == '\n' || prefix.back() == ' ')) prefix.pop_back();
  prefix += head.empty() ? "\n  " : ",\n  ";
  prefix += nlohmann::json(key).dump() + ": [";
  const fs::path tmp = temporary_next_to(file_, ".tmp.");
  auto fail = [&](const std::string& why) {
    std::error_code ignore;
    fs::remove(tmp, ignore);
    throw std::runtime_error(why);
  };
  std::uintmax_t bytes = 0;
  {
    std::ifstream in(spool_, std::ios::binary);
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!in || !out) fail("cannot open '" + tmp.string() + "' for writing (for '" + file_.string() + "')");
    out << prefix;
    bytes += prefix.size();
    std::string line;
    std::uintmax_t lines = 0;
    while (std::getline(in, line)) {
      const std::string sep = lines++ ? ",\n    " : "\n    ";
      out << sep << line;
      bytes += sep.size() + line.size();
    }
    if (lines != count_) fail("'" + file_.string() + "': read " + std::to_string(lines) + " spooled elements of " +
                              std::to_string(count_) + " (temporary '" + spool_.string() + "')");
    const std::string suffix = lines ? "\n  ]\n}\n" : "]\n}\n";
    out << suffix;
    bytes += suffix.size();
    out.close();
    if (!out) fail("cannot write '" + file_.string() + "' (temporary '" + tmp.string() + "')");
  }
  std::error_code ec;
  if (!fs::is_regular_file(tmp, ec) || fs::file_size(tmp, ec) != bytes || ec)
    fail("'" + file_.string() + "' did not keep the " + std::to_string(bytes) + " bytes written (temporary '" +
         tmp.string() + "')");
  fs::rename(tmp, file_, ec);
  if (ec) fail("cannot rename '" + tmp.string() + "' to '" + file_.string() + "': " + ec.message());
}

}  // namespace xpbd_demos
