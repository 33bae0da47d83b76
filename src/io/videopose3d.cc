#include "io/videopose3d.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <set>
#include <string_view>
#include <utility>

#include "core/error.h"
#include "io/file_util.h"

namespace motionfork {

namespace {

constexpr const char* kColumns[] = {"subject", "action", "frames", "joints", "fps", "file"};
constexpr int kNumColumns = 6;

std::vector<std::string_view> SplitTabs(std::string_view s) {
  std::vector<std::string_view> out;
  size_t begin = 0;
  for (;;) {
    const size_t end = s.find('\t', begin);
    if (end == std::string_view::npos) {
      out.push_back(s.substr(begin));
      return out;
    }
    out.push_back(s.substr(begin, end - begin));
    begin = end + 1;
  }
}

std::string Quote(std::string_view s) {
  std::string out = "'";
  for (size_t i = 0; i < s.size() && i < 60; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    out += c >= 0x20 ? static_cast<char>(c) : '?';
  }
  return out + (s.size() > 60 ? "...'" : "'");
}

}  // namespace

std::vector<VideoPose3dTake> ReadVideoPose3dManifest(const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path manifest = fs::path(dir) / "manifest.tsv";
  const std::string src = manifest.string();
  std::error_code ec;
  if (!fs::is_regular_file(manifest, ec)) {
    throw FormatError(
        FormatMessage(src, "",
                      "no manifest: expected a folder made by tools/videopose3d_to_motionfork.py "
                      "(convert data_3d_h36m.npz / data_3d_humaneva15.npz with it first)"));
  }
  const std::string bytes = ReadFileBytes(src);

  std::vector<VideoPose3dTake> takes;
  std::set<std::pair<std::string, std::string>> seen;
  int index[kNumColumns];
  size_t num_header_fields = 0;
  bool have_header = false;
  size_t begin = 0;
  for (int number = 1; begin < bytes.size(); ++number) {
    size_t end = bytes.find('\n', begin);
    if (end == std::string::npos) end = bytes.size();
    std::string_view line(bytes.data() + begin, end - begin);
    begin = end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) continue;
    const std::string where = "line " + std::to_string(number);
    const std::vector<std::string_view> fields = SplitTabs(line);

    if (!have_header) {
      // Columns by name, so a later version may add columns without breaking old readers.
      for (int c = 0; c < kNumColumns; ++c) {
        index[c] = -1;
        for (size_t f = 0; f < fields.size(); ++f) {
          if (fields[f] == kColumns[c]) index[c] = static_cast<int>(f);
        }
        if (index[c] < 0) {
          throw FormatError(FormatMessage(
              src, where,
              "expected the header subject<TAB>action<TAB>frames<TAB>joints<TAB>fps<TAB>file, "
              "found " +
                  Quote(line) + " (no column '" + kColumns[c] + "')"));
        }
      }
      num_header_fields = fields.size();
      have_header = true;
      continue;
    }

    if (fields.size() != num_header_fields) {
      throw FormatError(FormatMessage(src, where,
                                      "expected " + std::to_string(num_header_fields) +
                                          " tab-separated fields, found " +
                                          std::to_string(fields.size())));
    }
    auto field = [&](int c) { return fields[static_cast<size_t>(index[c])]; };
    auto parse_int = [&](int c) {
      const std::string_view f = field(c);
      int value = 0;
      const auto [ptr, err] = std::from_chars(f.data(), f.data() + f.size(), value);
      if (err != std::errc() || ptr != f.data() + f.size() || value < 1) {
        throw FormatError(FormatMessage(src, where,
                                        std::string("expected ") + kColumns[c] +
                                            " to be a whole number >= 1, found " + Quote(f)));
      }
      return value;
    };
    VideoPose3dTake take;
    take.subject = std::string(field(0));
    take.action = std::string(field(1));
    if (take.subject.empty() || take.action.empty()) {
      throw FormatError(FormatMessage(src, where,
                                      "expected a non-empty subject and action, found " +
                                          Quote(take.subject) + " and " + Quote(take.action)));
    }
    take.frames = parse_int(2);
    take.joints = parse_int(3);
    {
      const std::string_view f = field(4);
      const auto [ptr, err] = std::from_chars(f.data(), f.data() + f.size(), take.fps);
      if (err != std::errc() || ptr != f.data() + f.size() || !std::isfinite(take.fps) ||
          !(take.fps > 0)) {
        throw FormatError(
            FormatMessage(src, where, "expected fps to be a number > 0 (Hz), found " + Quote(f)));
      }
    }
    const std::string_view file = field(5);
    if (file.empty()) {
      throw FormatError(FormatMessage(src, where, "expected a file name, found an empty field"));
    }
    const fs::path file_path(std::string{file});
    take.path = file_path.is_absolute() ? file_path.string() : (fs::path(dir) / file_path).string();
    if (!seen.emplace(take.subject, take.action).second) {
      throw FormatError(FormatMessage(
          src, where,
          "duplicate take: subject " + Quote(take.subject) + ", action " + Quote(take.action)));
    }
    takes.push_back(std::move(take));
  }
  if (!have_header) {
    throw FormatError(FormatMessage(src, "",
                                    "empty manifest: expected the header "
                                    "subject<TAB>action<TAB>frames<TAB>joints<TAB>fps<TAB>file"));
  }
  if (takes.empty()) {
    throw FormatError(FormatMessage(src, "", "the manifest lists no takes"));
  }
  return takes;
}

}  // namespace motionfork
