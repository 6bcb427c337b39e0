#include "stripweave/io/mesh_text.h"

#include "stripweave/core/error.h"

#include <cerrno>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sys/stat.h>

namespace stripweave {

void throw_mesh_read(const std::string& path, const std::string& what) {
  throw InputError("cannot read mesh file '" + path + "': " + what);
}

std::string read_regular_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) throw_mesh_read(path, "file does not exist");
    throw_mesh_read(path, std::string("cannot open it (") + std::strerror(errno) + ")");
  }
  if (S_ISDIR(st.st_mode)) throw_mesh_read(path, "it is a directory");
  if (!S_ISREG(st.st_mode)) throw_mesh_read(path, "it is not a regular file (a device, pipe or socket)");
  if (st.st_size == 0) throw_mesh_read(path, "file is empty");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_mesh_read(path, std::string("cannot open it (") + std::strerror(errno) + ")");
  std::string bytes(static_cast<std::size_t>(st.st_size), '\0');
  in.read(bytes.data(), st.st_size);
  bytes.resize(static_cast<std::size_t>(in.gcount()));  // a file that shrank meanwhile
  return bytes;
}

MeshText::MeshText(std::string path, const std::string& bytes) : path_(std::move(path)), rest_(bytes) {}

bool MeshText::next_line() {
  while (!rest_.empty()) {
    const std::size_t end = rest_.find('\n');
    std::string_view line = rest_.substr(0, end);
    rest_ = end == std::string_view::npos ? std::string_view() : rest_.substr(end + 1);
    ++line_;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    tokens_.clear();
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      const std::size_t start = i;
      while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      if (i > start) tokens_.push_back(line.substr(start, i - start));
    }
    if (!tokens_.empty()) return true;
  }
  return false;
}

void MeshText::fail(const std::string& what) const {
  throw_mesh_read(path_, "line " + std::to_string(line_) + ": " + what);
}

double MeshText::number(std::size_t token, const char* what) const {
  if (token >= tokens_.size()) fail(std::string("the line ends where ") + what + " is due");
  const std::string_view t = tokens_[token];
  double value = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(value))
    fail(std::string(what) + " '" + std::string(t) + "' is not a finite number");
  return value;
}

long long MeshText::integer(std::size_t token, const char* what) const {
  if (token >= tokens_.size()) fail(std::string("the line ends where ") + what + " is due");
  const std::string_view t = tokens_[token];
  long long value = 0;
  const char* begin = t.data() + (!t.empty() && t[0] == '+' ? 1 : 0);
  const auto [end, ec] = std::from_chars(begin, t.data() + t.size(), value);
  if (ec != std::errc() || end != t.data() + t.size())
    fail(std::string(what) + " '" + std::string(t) + "' is not a whole number");
  return value;
}

}  // namespace stripweave
