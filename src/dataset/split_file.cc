#include "dataset/split_file.h"

#include <sstream>

#include "core/error.h"
#include "io/file_util.h"

namespace motionfork {

std::map<std::string, std::string> ReadSplitFile(const std::string& path) {
  const std::string text = ReadFileBytes(path);
  std::map<std::string, std::string> out;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const size_t tab = line.find('\t');
    const std::string where = "line " + std::to_string(line_no);
    if (tab == std::string::npos) {
      throw FormatError(
          FormatMessage(path, where, "expected 'split<TAB>clip', found '" + line + "'"));
    }
    const std::string split = line.substr(0, tab);
    std::string clip = line.substr(tab + 1);
    if (split != "train" && split != "test") {
      throw FormatError(
          FormatMessage(path, where, "expected split 'train' or 'test', found '" + split + "'"));
    }
    const size_t dot = clip.rfind('.');
    if (dot != std::string::npos && dot > 0) clip = clip.substr(0, dot);
    if (clip.empty())
      throw FormatError(FormatMessage(path, where, "expected a clip name, found none"));
    if (!out.emplace(clip, split).second) {
      throw FormatError(FormatMessage(path, where, "clip '" + clip + "' is listed twice"));
    }
  }
  if (out.empty())
    throw FormatError(FormatMessage(path, "", "expected at least one clip, found none"));
  return out;
}

}  // namespace motionfork
