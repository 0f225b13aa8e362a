#include "common/text_file.h"

#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"

namespace femsimp {

absl::StatusOr<std::string> ReadTextFile(const std::string& what, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  if (in) text << in.rdbuf();
  if (!in || in.bad()) return absl::NotFoundError(absl::StrCat(what, ": cannot read ", path));
  return text.str();
}

}  // namespace femsimp
