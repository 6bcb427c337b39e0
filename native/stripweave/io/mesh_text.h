// MeshText: a mesh file's text, line by line, with strict number parsing and
// errors that name the file and the line (the mesh readers' common part).
//
//   MeshText text(path, bytes);          // bytes: the whole file
//   while (text.next_line()) { text.tokens() ... text.number(i) ... }
//   text.fail("what was wrong")          // InputError "cannot read mesh file
//                                        // 'path': line N: what was wrong"
// Tokens are separated by blanks; a '#' starts a comment. A number must be
// the whole token: "1.5x" or "1.5" where an index is due are refused, never
// read as a prefix (CGAL read "f 1.5 2 3" as "f 1 2 3").
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace stripweave {

// The whole content of a regular file; InputError for a device, pipe or
// socket (a FIFO or /dev/zero named .stl was read forever) or a directory.
std::string read_regular_file(const std::string& path);

class MeshText {
 public:
  // `bytes` is viewed, not copied: it must outlive the MeshText.
  MeshText(std::string path, const std::string& bytes);
  bool next_line();  // false at the end of the file
  const std::vector<std::string_view>& tokens() const { return tokens_; }
  long long line() const { return line_; }
  double number(std::size_t token, const char* what) const;
  long long integer(std::size_t token, const char* what) const;
  [[noreturn]] void fail(const std::string& what) const;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string_view rest_;
  std::vector<std::string_view> tokens_;
  long long line_ = 0;
};

// "cannot read mesh file 'path': what" as an InputError.
[[noreturn]] void throw_mesh_read(const std::string& path, const std::string& what);

}  // namespace stripweave
