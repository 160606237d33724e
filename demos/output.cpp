#include "demos/output.hpp"

#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <unistd.h>

namespace xpbd_demos {

namespace fs = std::filesystem;

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
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot open '" + tmp.string() + "' for writing");
    out << text;
    out.flush();
    if (!out) {
      out.close();
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write '" + tmp.string() + "'");
    }
  }
  fs::rename(tmp, file, ec);
  if (ec) {
    std::error_code ignore;
    fs::remove(tmp, ignore);
    throw std::runtime_error("cannot rename '" + tmp.string() + "' to '" + file.string() +
                             "': " + ec.message());
  }
}

}  // namespace xpbd_demos
