#include "io/csv.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.h"
#include "io/file_util.h"
#include "io/motion_limits.h"

namespace motionfork {

namespace {

struct Line {
  std::string_view text;  // without the line break (LF or CRLF)
  int64_t number = 0;     // 1-based
};

// The lines of a buffer one at a time: memory stays constant however many lines there are.
class LineCursor {
 public:
  explicit LineCursor(std::string_view bytes) : bytes_(bytes) {}
  // The next line into *line; false at the end of the buffer.
  bool Next(Line* line) {
    if (begin_ >= bytes_.size()) return false;
    size_t end = bytes_.find('\n', begin_);
    const size_t next = end == std::string_view::npos ? bytes_.size() : end + 1;
    if (end == std::string_view::npos) end = bytes_.size();
    std::string_view text = bytes_.substr(begin_, end - begin_);
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    *line = {text, ++number_};
    begin_ = next;
    return true;
  }

 private:
  std::string_view bytes_;
  size_t begin_ = 0;
  int64_t number_ = 0;
};

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Splits on a single separator character; "a,,b" gives an empty middle field.
void SplitFields(std::string_view s, char sep, std::vector<std::string_view>* out) {
  out->clear();
  size_t begin = 0;
  for (;;) {
    const size_t end = s.find(sep, begin);
    if (end == std::string_view::npos) {
      out->push_back(s.substr(begin));
      return;
    }
    out->push_back(s.substr(begin, end - begin));
    begin = end + 1;
  }
}

// A field quoted in an error message: printable, bounded length.
std::string Quote(std::string_view s) {
  std::string out = "'";
  for (size_t i = 0; i < s.size() && i < 40; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (s.size() > 40) out += "...";
  return out + "'";
}

std::string LineLocation(int64_t line) { return "line " + std::to_string(line); }

std::string JoinNames(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + names[i];
  return out;
}

// Parses a whole field as a float. Values too small for float32 become (signed) zero; values too
// large are an error. Anything but a plain decimal number (hex, "1e", "1,5") is kNotANumber.
enum class NumberStatus { kOk, kNotANumber, kOutOfRange };
NumberStatus ParseFloat(std::string_view field, float* value) {
  if (!field.empty() && field.front() == '+') {  // from_chars takes '-' but not '+'
    field.remove_prefix(1);
    if (!field.empty() && (field.front() == '+' || field.front() == '-')) {
      return NumberStatus::kNotANumber;
    }
  }
  if (field.empty()) return NumberStatus::kNotANumber;
  const char* first = field.data();
  const char* last = field.data() + field.size();
  auto [ptr, ec] = std::from_chars(first, last, *value);
  if (ec == std::errc() && ptr == last) return NumberStatus::kOk;
  if (ec != std::errc::result_out_of_range || ptr != last) return NumberStatus::kNotANumber;
  // Out of float range: an underflow (|x| < 1e-45) is zero, an overflow an error.
  double d = 0;
  auto [dptr, dec] = std::from_chars(first, last, d);
  bool underflow;
  if (dec == std::errc() && dptr == last) {
    underflow = std::fabs(d) < 1.0;
  } else {
    underflow =
        field.find("e-") != std::string_view::npos || field.find("E-") != std::string_view::npos;
  }
  if (!underflow) return NumberStatus::kOutOfRange;
  *value = field.front() == '-' ? -0.0f : 0.0f;
  return NumberStatus::kOk;
}

struct Column {
  int joint;
  int axis;  // 0, 1, 2 = x, y, z
};

struct ParsedHeader {
  std::vector<std::string> names;  // as written, one per column
  std::vector<int> axes;           // one per column
};

ParsedHeader ParseHeader(const Line& line, const std::string& source) {
  ParsedHeader header;
  std::vector<std::string_view> fields;
  SplitFields(line.text, ',', &fields);
  for (size_t c = 0; c < fields.size(); ++c) {
    std::string_view f = Trim(fields[c]);
    if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
    const size_t dot = f.rfind('.');
    int axis = -1;
    if (dot != std::string_view::npos && dot > 0 && dot + 2 == f.size()) {
      const char a = f[dot + 1];
      axis = (a == 'x' || a == 'X')   ? 0
             : (a == 'y' || a == 'Y') ? 1
             : (a == 'z' || a == 'Z') ? 2
                                      : -1;
    }
    if (axis < 0) {
      throw FormatError(FormatMessage(
          source, LineLocation(line.number) + ", column " + std::to_string(c + 1),
          "expected a header column named <joint>.x, <joint>.y or <joint>.z, found " + Quote(f)));
    }
    header.names.emplace_back(f.substr(0, dot));
    header.axes.push_back(axis);
  }
  return header;
}

// Maps header columns to (joint, axis) of the skeleton, or builds a skeleton from the header when
// none is given. Every joint must have exactly one x, y and z column.
std::vector<Column> MapColumns(const ParsedHeader& header, const Line& line,
                               const std::string& source, const std::string& skeleton_name,
                               std::shared_ptr<const Skeleton>* skeleton) {
  const std::string where = LineLocation(line.number);
  std::vector<Column> columns(header.names.size());
  std::vector<std::string> order;  // joint names in order of first appearance (no skeleton)
  if (*skeleton) {
    std::vector<std::string> unknown;
    for (size_t c = 0; c < header.names.size(); ++c) {
      const auto j = (*skeleton)->Find(header.names[c]);
      if (!j) {
        bool seen = false;
        for (const auto& u : unknown) seen = seen || u == header.names[c];
        if (!seen) unknown.push_back(header.names[c]);
        continue;
      }
      columns[c] = {*j, header.axes[c]};
    }
    if (!unknown.empty()) {
      throw FormatError(
          FormatMessage(source, where,
                        "unknown joint name" + std::string(unknown.size() > 1 ? "s " : " ") +
                            JoinNames(unknown) + " (skeleton '" + (*skeleton)->name() +
                            "' has joints " + JoinNames((*skeleton)->joint_names()) + ")"));
    }
  } else {
    std::map<std::string, int> index;
    for (size_t c = 0; c < header.names.size(); ++c) {
      auto [it, inserted] = index.emplace(header.names[c], static_cast<int>(order.size()));
      if (inserted) order.push_back(header.names[c]);
      columns[c] = {it->second, header.axes[c]};
    }
  }

  const int num_joints = *skeleton ? (*skeleton)->num_joints() : static_cast<int>(order.size());
  if (num_joints > kMaxMotionJoints) {
    throw FormatError(FormatMessage(source, where,
                                    "the header names " + std::to_string(num_joints) +
                                        " joints; expected at most " +
                                        std::to_string(kMaxMotionJoints) + " per motion"));
  }
  const auto& joint_names = *skeleton ? (*skeleton)->joint_names() : order;
  std::vector<int> seen(static_cast<size_t>(num_joints) * 3, 0);
  for (size_t c = 0; c < columns.size(); ++c) {
    int& s = seen[static_cast<size_t>(columns[c].joint) * 3 + columns[c].axis];
    if (s) {
      throw FormatError(FormatMessage(source, where + ", column " + std::to_string(c + 1),
                                      "duplicate column " +
                                          Quote(header.names[c] + "." + "xyz"[columns[c].axis]) +
                                          " (first seen in column " + std::to_string(s) + ")"));
    }
    s = static_cast<int>(c + 1);
  }
  std::vector<std::string> missing;
  for (int j = 0; j < num_joints; ++j) {
    std::string axes;
    for (int a = 0; a < 3; ++a) {
      if (!seen[static_cast<size_t>(j) * 3 + a])
        axes += std::string(axes.empty() ? "" : "/") + "xyz"[a];
    }
    if (!axes.empty()) missing.push_back(joint_names[j] + " (" + axes + ")");
  }
  if (!missing.empty()) {
    throw FormatError(FormatMessage(
        source, where,
        "missing columns for joint" + std::string(missing.size() > 1 ? "s " : " ") +
            JoinNames(missing) + "; expected <joint>.x,<joint>.y,<joint>.z for every joint"));
  }

  if (!*skeleton) {
    bool plain = true;  // j0, j1, ...: what an anonymous skeleton writes
    for (int j = 0; j < num_joints; ++j) plain = plain && order[j] == "j" + std::to_string(j);
    try {
      if (plain) {
        *skeleton = std::make_shared<const Skeleton>(Skeleton::Anonymous(num_joints));
      } else {
        // Named joints but no tree (a CSV stores none).
        *skeleton = std::make_shared<const Skeleton>(
            Skeleton::Unlinked(skeleton_name.empty() ? "unlinked" : skeleton_name, order));
      }
    } catch (const std::invalid_argument& e) {
      throw FormatError(FormatMessage(source, where, std::string("bad joint names: ") + e.what()));
    }
  }
  return columns;
}

struct Metadata {
  std::optional<double> fps;
  float scale = 1.0f;  // to metres
  std::string skeleton_name;
};

// "# motionfork positions; fps=30; unit=m; skeleton=bandai": key=value tokens separated by ';'
// or spaces; other words are ignored.
void ParseComment(const Line& line, const std::string& source, Metadata* meta) {
  std::string_view text = line.text.substr(1);
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ';' || text[i] == ' ' || text[i] == '\t')) ++i;
    size_t end = i;
    while (end < text.size() && text[end] != ';' && text[end] != ' ' && text[end] != '\t') ++end;
    const std::string_view token = text.substr(i, end - i);
    i = end;
    const size_t eq = token.find('=');
    if (eq == std::string_view::npos) continue;
    const std::string_view key = token.substr(0, eq), value = token.substr(eq + 1);
    if (key == "fps") {
      double fps = 0;
      auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), fps);
      if (ec != std::errc() || ptr != value.data() + value.size() || !std::isfinite(fps) ||
          !(fps > 0)) {
        throw FormatError(
            FormatMessage(source, LineLocation(line.number),
                          "expected fps=<frames per second > 0>, found fps=" + Quote(value)));
      }
      meta->fps = fps;
    } else if (key == "unit") {
      if (value == "m") {
        meta->scale = 1.0f;
      } else if (value == "cm") {
        meta->scale = 0.01f;
      } else if (value == "mm") {
        meta->scale = 0.001f;
      } else {
        throw FormatError(
            FormatMessage(source, LineLocation(line.number),
                          "expected unit=m, unit=cm or unit=mm, found unit=" + Quote(value)));
      }
    } else if (key == "skeleton") {
      meta->skeleton_name = std::string(value);
    }
  }
}

// A missing value in a CSV motion: an empty field, "nan" or "NaN" (as numpy and pandas write it).
bool IsMissingField(std::string_view f) {
  return f.empty() || f == "nan" || f == "NaN" || f == "NAN";
}

Motion ParseCsvMotion(std::string_view bytes, const std::string& source,
                      std::shared_ptr<const Skeleton> skeleton, double fallback_fps,
                      std::vector<uint8_t>* missing) {
  if (missing) missing->clear();
  if (bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);  // UTF-8 byte order mark
  LineCursor lines(bytes);
  Metadata meta;
  Line header_line;
  bool found_header = false;
  while (!found_header && lines.Next(&header_line)) {
    const std::string_view t = Trim(header_line.text);
    if (t.empty()) continue;
    if (t.front() != '#') found_header = true;
    if (!found_header) ParseComment(header_line, source, &meta);
  }
  if (!found_header) {
    throw FormatError(FormatMessage(
        source, "",
        std::string(bytes.empty() ? "empty file" : "no header line") +
            ": expected a header of <joint>.x,<joint>.y,<joint>.z columns, then one row per "
            "frame"));
  }
  const ParsedHeader header = ParseHeader(header_line, source);
  const std::vector<Column> columns =
      MapColumns(header, header_line, source, meta.skeleton_name, &skeleton);
  const size_t per_frame = static_cast<size_t>(skeleton->num_joints()) * 3;

  std::vector<float> positions;
  std::vector<std::string_view> fields;
  size_t frames = 0;
  Line line;
  while (lines.Next(&line)) {
    const std::string_view t = Trim(line.text);
    if (t.empty() || t.front() == '#') continue;
    SplitFields(line.text, ',', &fields);
    if (fields.size() != columns.size()) {
      throw FormatError(FormatMessage(
          source, LineLocation(line.number),
          "expected " + std::to_string(columns.size()) + " columns (as in the header on line " +
              std::to_string(header_line.number) + "), found " + std::to_string(fields.size())));
    }
    if (static_cast<int64_t>(frames) >= kMaxMotionFrames) {
      throw FormatError(FormatMessage(
          source, LineLocation(line.number),
          "more than " + std::to_string(kMaxMotionFrames) + " frames, the limit per motion"));
    }
    positions.resize(positions.size() + per_frame);
    if (missing) missing->resize(positions.size(), 0);
    float* frame = positions.data() + frames * per_frame;
    for (size_t c = 0; c < fields.size(); ++c) {
      const std::string_view f = Trim(fields[c]);
      if (missing && IsMissingField(f)) {
        (*missing)[frames * per_frame + static_cast<size_t>(columns[c].joint) * 3 +
                   columns[c].axis] = 1;
        frame[static_cast<size_t>(columns[c].joint) * 3 + columns[c].axis] = 0.0f;
        continue;
      }
      float value = 0;
      const NumberStatus status = ParseFloat(f, &value);
      value *= meta.scale;
      if (status != NumberStatus::kOk || !std::isfinite(value)) {
        // Built only on error: this loop runs once per number of the file.
        const std::string where = LineLocation(line.number) + ", column " + std::to_string(c + 1) +
                                  " (" + header.names[c] + "." + "xyz"[header.axes[c]] + ")";
        const std::string what = status == NumberStatus::kNotANumber
                                     ? "expected a number, found " + Quote(f)
                                 : status == NumberStatus::kOutOfRange
                                     ? "number " + Quote(f) + " is outside the float32 range"
                                     : "expected a finite number, found " + Quote(f);
        throw FormatError(FormatMessage(source, where, what));
      }
      frame[static_cast<size_t>(columns[c].joint) * 3 + columns[c].axis] = value;
    }
    ++frames;
  }
  if (frames == 0) {
    throw FormatError(FormatMessage(source, "",
                                    "no data rows after the header on line " +
                                        std::to_string(header_line.number) +
                                        ": expected at least one frame"));
  }
  const double fps = meta.fps ? *meta.fps : fallback_fps;
  if (!std::isfinite(fps) || !(fps > 0)) {
    throw FormatError(FormatMessage(source, "",
                                    "no 'fps=' comment in the file and no valid fallback frame "
                                    "rate given (got " +
                                        std::to_string(fallback_fps) + " Hz)"));
  }
  try {
    return Motion(std::move(skeleton), fps, std::move(positions));
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(source, "", e.what()));  // every value was checked already
  }
}

void AppendNumber(std::string* out, float value) {
  char buf[32];
  // Shortest text that reads back to the same float32 (at most 9 significant digits).
  const auto r = std::to_chars(buf, buf + sizeof(buf), value);
  out->append(buf, r.ptr);
}

}  // namespace

Motion ReadCsvMotion(const std::string& path, std::shared_ptr<const Skeleton> skeleton, double fps,
                     std::vector<uint8_t>* missing) {
  const std::string bytes = ReadFileBytes(path, RequireTextHead(path, "a CSV text file"));
  return ParseCsvMotion(bytes, path, std::move(skeleton), fps, missing);
}

void WriteCsvMotion(const std::string& path, const Motion& motion) {
  const Skeleton& skeleton = motion.skeleton();
  for (const std::string& name : skeleton.joint_names()) {
    const bool bad = name.empty() || name.find_first_of(",\"\r\n") != std::string::npos ||
                     Trim(name).size() != name.size() || name.front() == '#';
    if (bad) {
      throw std::invalid_argument("WriteCsvMotion: joint name " + Quote(name) +
                                  " cannot be a CSV header (expected no commas, quotes, line "
                                  "breaks, '#' at the start or surrounding spaces)");
    }
  }
  std::string skeleton_name = skeleton.name();
  for (char& c : skeleton_name) {
    if (c == ';' || c == ' ' || c == '\t' || c == '\r' || c == '\n') c = '_';
  }
  char fps_text[32];
  const auto r = std::to_chars(fps_text, fps_text + sizeof(fps_text), motion.fps());

  std::string out = "# motionfork positions; fps=" + std::string(fps_text, r.ptr) +
                    "; unit=m; skeleton=" + skeleton_name + "\n";
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    for (const char* axis : {".x", ".y", ".z"}) {
      if (j > 0 || axis[1] != 'x') out += ',';
      out += skeleton.joint_name(j);
      out += axis;
    }
  }
  out += '\n';
  const auto& p = motion.positions();
  const size_t per_frame = static_cast<size_t>(motion.num_joints()) * 3;
  out.reserve(out.size() + p.size() * 12);
  for (size_t i = 0; i < p.size(); ++i) {
    AppendNumber(&out, p[i]);
    out += (i + 1) % per_frame == 0 ? '\n' : ',';
  }
  WriteFileAtomically(path, out);
}

}  // namespace motionfork
