#include "io/bvh.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/skeleton.h"
#include "io/file_util.h"
#include "io/motion_limits.h"

// Layout: the header (hierarchy, Frames, Frame Time) is small and read through a whitespace
// tokenizer; the motion section, almost all of the bytes, is read by a scanner over the buffer
// with std::from_chars and evaluated frame by frame with per-joint channel layouts resolved once,
// so the per-frame loop does not allocate. Line numbers are counted only when an error is raised.
// Frames in messages are counted from 0, as everywhere in Motion; the line number is given too.

namespace motionfork {

namespace {

// Limits that keep a damaged or hostile file from costing unbounded memory or time
// (io/motion_limits.h).
constexpr int kMaxNodes = kMaxMotionJoints;  // joints + End Sites
constexpr uint64_t kMaxPositionValues = kMaxMotionValues;
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

// Channel kinds; the value is the axis (0 = X, 1 = Y, 2 = Z) plus 3 for rotations.
enum class Channel : uint8_t { kXpos = 0, kYpos, kZpos, kXrot, kYrot, kZrot };

// One ROOT, JOINT or End Site of the hierarchy, in file (depth-first) order.
struct Node {
  std::string name;
  int parent = -1;
  bool end_site = false;
  bool has_offset = false;
  bool has_channels = false;
  double offset[3] = {0, 0, 0};  // file units
  int first_channel = 0;         // index of this node's first value in a frame line
  int num_channels = 0;
  Channel channels[6] = {};
  size_t decl_offset = 0;  // byte offset of the ROOT/JOINT/End keyword, for messages
};

bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}
// Whitespace inside a line of the motion section.
bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }
bool IsLineEnd(char c) { return c == '\n' || c == '\r'; }

bool EqualsNoCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
    if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
    if (x != y) return false;
  }
  return true;
}

// A token as it may appear in an error message: at most 40 characters, control and non-ASCII
// bytes escaped, so a binary file does not produce an unreadable message.
std::string Quote(std::string_view token) {
  std::string out = "'";
  const size_t n = std::min<size_t>(token.size(), 40);
  for (size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      static const char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (token.size() > n) out += "...";
  out += "'";
  return out;
}

bool ParseChannelName(std::string_view s, Channel* out) {
  static const std::pair<const char*, Channel> kNames[] = {
      {"Xposition", Channel::kXpos}, {"Yposition", Channel::kYpos}, {"Zposition", Channel::kZpos},
      {"Xrotation", Channel::kXrot}, {"Yrotation", Channel::kYrot}, {"Zrotation", Channel::kZrot}};
  for (const auto& [name, ch] : kNames) {
    if (EqualsNoCase(s, name)) {
      *out = ch;
      return true;
    }
  }
  return false;
}

const char* ChannelName(Channel c) {
  static const char* kNames[] = {"Xposition", "Yposition", "Zposition",
                                 "Xrotation", "Yrotation", "Zrotation"};
  return kNames[static_cast<int>(c)];
}

// Parses a whole token as a finite double (a leading '+' is accepted). Returns false otherwise.
bool ParseFiniteDouble(std::string_view s, double* out) {
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+' && e - b > 1 && (b[1] == '.' || (b[1] >= '0' && b[1] <= '9'))) ++b;
  const auto r = std::from_chars(b, e, *out);
  return r.ec == std::errc() && r.ptr == e && std::isfinite(*out);
}

// Number of decimal places a number was written with ("0.008333" -> 6, "8.333e-3" -> 6), or -1.
int DecimalsOf(std::string_view s) {
  const size_t dot = s.find('.');
  const size_t exp_pos = s.find_first_of("eE");
  int frac = 0;
  if (dot != std::string_view::npos) {
    const size_t stop = exp_pos == std::string_view::npos ? s.size() : exp_pos;
    if (stop < dot) return -1;
    frac = static_cast<int>(stop - dot - 1);
  }
  int exponent = 0;
  if (exp_pos != std::string_view::npos) {
    const char* b = s.data() + exp_pos + 1;
    if (b < s.data() + s.size() && *b == '+') ++b;
    const auto r = std::from_chars(b, s.data() + s.size(), exponent);
    if (r.ec != std::errc() || exponent < -300 || exponent > 300) return -1;
  }
  return frac - exponent;
}

// fps = 1 / frame_time, snapped to the nearest integer n when within 1e-3 Hz of it, or when the
// Frame Time is 1/n written to the precision it was printed with and the two rates agree to
// 0.1 % (exporters print 120 Hz as "0.008333", which is 120.005 Hz).
double FpsFromFrameTime(double frame_time, std::string_view token) {
  const double fps = 1.0 / frame_time;
  const double n = std::round(fps);
  if (n < 1) return fps;
  if (std::abs(fps - n) <= 1e-3) return n;
  const int decimals = DecimalsOf(token);
  if (decimals < 0 || decimals > 300) return fps;
  const double half_unit = 0.5 * std::pow(10.0, -decimals);
  if (std::abs(1.0 / n - frame_time) <= half_unit * (1 + 1e-9) && std::abs(fps - n) <= 1e-3 * n) {
    return n;
  }
  return fps;
}

struct Token {
  std::string_view text;  // empty at the end of the input
  size_t offset = 0;      // byte offset of the token in the input
};

// The input plus everything needed to word an error. Line numbers are computed only when an
// error is raised.
class Source {
 public:
  Source(std::string_view text, const std::string& name) : text_(text), name_(name) {}

  std::string_view text() const { return text_; }

  // 1-based line of a byte offset; "\n", "\r\n" and a lone "\r" each end a line.
  int LineAt(size_t offset) const {
    offset = std::min(offset, text_.size());
    int line = 1;
    for (size_t i = 0; i < offset; ++i) {
      if (text_[i] == '\n' ||
          (text_[i] == '\r' && (i + 1 >= text_.size() || text_[i + 1] != '\n'))) {
        ++line;
      }
    }
    return line;
  }

  [[noreturn]] void FailAt(size_t offset, const std::string& what) const {
    throw FormatError(FormatMessage(name_, "line " + std::to_string(LineAt(offset)), what));
  }
  [[noreturn]] void FailAtFrame(int64_t frame, size_t offset, const std::string& what) const {
    throw FormatError(FormatMessage(
        name_, "frame " + std::to_string(frame) + " (line " + std::to_string(LineAt(offset)) + ")",
        what));
  }
  [[noreturn]] void Fail(const std::string& what) const {
    throw FormatError(FormatMessage(name_, "", what));
  }

 private:
  std::string_view text_;
  const std::string& name_;
};

// Whitespace-separated tokens of the hierarchy and the motion header.
class Tokenizer {
 public:
  Tokenizer(std::string_view text, size_t pos) : text_(text), pos_(pos) {}

  Token Next() {
    while (pos_ < text_.size() && IsSpace(text_[pos_])) ++pos_;
    const size_t start = pos_;
    while (pos_ < text_.size() && !IsSpace(text_[pos_])) ++pos_;
    return Token{text_.substr(start, pos_ - start), start};
  }
  Token Peek() {
    const size_t saved = pos_;
    Token t = Next();
    pos_ = saved;
    return t;
  }
  size_t pos() const { return pos_; }

 private:
  std::string_view text_;
  size_t pos_;
};

std::string Describe(const Token& t) {
  return t.text.empty() ? "the end of the file" : Quote(t.text);
}

// Everything the motion section needs from the header.
struct Header {
  std::vector<Node> nodes;
  int total_channels = 0;
  int64_t num_frames = 0;
  double frame_time = 0;
  std::string_view frame_time_token;
  size_t frames_offset = 0;  // of the "Frames:" label
  size_t data_begin = 0;     // first byte after the Frame Time line
};

// Reads "<label>:" (also "<label> :" and "<label>:<value>"), returning the value token.
Token ReadLabelled(Tokenizer& tok, const Source& src, std::string_view label,
                   const std::string& expected) {
  Token t = tok.Next();
  std::string_view s = t.text;
  if (s.size() >= label.size() && EqualsNoCase(s.substr(0, label.size()), label)) {
    s.remove_prefix(label.size());
    if (s.empty()) {
      Token colon = tok.Peek();
      if (colon.text == ":") {
        tok.Next();
        return tok.Next();
      }
      src.FailAt(t.offset, "expected " + expected + ", found " + Quote(t.text) + " without ':'");
    }
    if (s[0] == ':') {
      s.remove_prefix(1);
      if (s.empty()) return tok.Next();
      return Token{s, t.offset + label.size() + 1};
    }
  }
  src.FailAt(t.offset, "expected " + expected + ", found " + Describe(t));
}

Header ParseHeader(const Source& src, size_t start, const BvhOptions& options) {
  Header h;
  Tokenizer tok(src.text(), start);
  std::unordered_map<std::string, int> names;  // name -> node

  Token t = tok.Next();
  if (t.text.empty()) {
    src.FailAt(t.offset, "the file is empty; expected a BVH file starting with 'HIERARCHY'");
  }
  if (!EqualsNoCase(t.text, "HIERARCHY")) {
    src.FailAt(t.offset, "expected 'HIERARCHY' at the start of a BVH file, found " + Describe(t));
  }
  t = tok.Next();
  if (!EqualsNoCase(t.text, "ROOT")) {
    src.FailAt(t.offset, "expected 'ROOT <name>' after 'HIERARCHY', found " + Describe(t));
  }

  std::vector<int> open;  // nodes whose '{' is not closed yet, innermost last
  // Reads the name (or "Site") and '{' after ROOT/JOINT/End and opens the node.
  auto open_node = [&](const Token& keyword, int parent, bool end_site) {
    if (static_cast<int>(h.nodes.size()) >= kMaxNodes) {
      src.FailAt(keyword.offset, "too many joints: expected at most " + std::to_string(kMaxNodes) +
                                     " joints and End Sites, found more");
    }
    Node n;
    n.parent = parent;
    n.end_site = end_site;
    n.decl_offset = keyword.offset;
    const Token name = tok.Next();
    if (end_site) {
      if (!EqualsNoCase(name.text, "Site")) {
        src.FailAt(name.offset, "expected 'Site' after 'End', found " + Describe(name));
      }
      n.name = h.nodes[parent].name + "_End";
    } else {
      if (name.text.empty() || name.text == "{" || name.text == "}") {
        src.FailAt(name.offset, "expected a joint name after " + Quote(keyword.text) + ", found " +
                                    Describe(name));
      }
      n.name = std::string(name.text);
    }
    const Token brace = tok.Next();
    if (brace.text != "{") {
      src.FailAt(brace.offset, "expected '{' after " + Quote(keyword.text) + " " +
                                   Quote(end_site ? std::string_view("Site") : name.text) +
                                   ", found " + Describe(brace));
    }
    if (!end_site || options.include_end_sites) {
      const auto [it, inserted] = names.emplace(n.name, static_cast<int>(h.nodes.size()));
      if (!inserted) {
        src.FailAt(keyword.offset, "duplicate joint name " + Quote(n.name) +
                                       " (first declared at line " +
                                       std::to_string(src.LineAt(h.nodes[it->second].decl_offset)) +
                                       "); expected unique joint names");
      }
    }
    open.push_back(static_cast<int>(h.nodes.size()));
    h.nodes.push_back(std::move(n));
  };
  open_node(t, -1, false);

  while (!open.empty()) {
    const int j = open.back();
    const Token k = tok.Next();
    const std::string where = h.nodes[j].end_site
                                  ? "End Site of " + Quote(h.nodes[h.nodes[j].parent].name)
                                  : "joint " + Quote(h.nodes[j].name);
    if (k.text == "}") {
      if (!h.nodes[j].has_offset) {
        src.FailAt(k.offset, "expected 'OFFSET x y z' in " + where + " before '}'");
      }
      open.pop_back();
    } else if (EqualsNoCase(k.text, "OFFSET")) {
      if (h.nodes[j].has_offset) src.FailAt(k.offset, "second OFFSET in " + where);
      for (double& v : h.nodes[j].offset) {
        const Token num = tok.Next();
        if (!ParseFiniteDouble(num.text, &v)) {
          src.FailAt(num.offset, "expected 3 finite numbers after OFFSET in " + where + ", found " +
                                     Describe(num));
        }
      }
      h.nodes[j].has_offset = true;
    } else if (EqualsNoCase(k.text, "CHANNELS")) {
      Node& n = h.nodes[j];
      if (n.end_site) src.FailAt(k.offset, "an End Site cannot have CHANNELS");
      if (n.has_channels) src.FailAt(k.offset, "second CHANNELS in " + where);
      const Token count = tok.Next();
      int c = -1;
      const auto r = std::from_chars(count.text.data(), count.text.data() + count.text.size(), c);
      if (r.ec != std::errc() || r.ptr != count.text.data() + count.text.size() || c < 0 || c > 6) {
        src.FailAt(count.offset, "expected a number of channels (0..6) after CHANNELS in " + where +
                                     ", found " + Describe(count));
      }
      bool seen[6] = {false, false, false, false, false, false};
      for (int i = 0; i < c; ++i) {
        const Token name = tok.Next();
        Channel ch;
        if (!ParseChannelName(name.text, &ch)) {
          const bool keyword = name.text.empty() || name.text == "}" || name.text == "{" ||
                               EqualsNoCase(name.text, "JOINT") || EqualsNoCase(name.text, "End") ||
                               EqualsNoCase(name.text, "OFFSET") ||
                               EqualsNoCase(name.text, "MOTION");
          if (keyword) {
            src.FailAt(name.offset, "CHANNELS in " + where + " declares " + std::to_string(c) +
                                        " channels but lists only " + std::to_string(i) +
                                        " names; expected another channel name, found " +
                                        Describe(name));
          }
          src.FailAt(name.offset, "unknown channel name " + Quote(name.text) + " in " + where +
                                      "; expected one of Xposition Yposition Zposition "
                                      "Xrotation Yrotation Zrotation");
        }
        if (seen[static_cast<int>(ch)]) {
          src.FailAt(name.offset, "channel " + Quote(name.text) + " listed twice in " + where);
        }
        seen[static_cast<int>(ch)] = true;
        n.channels[i] = ch;
      }
      Channel extra;
      const Token next = tok.Peek();
      if (ParseChannelName(next.text, &extra)) {
        src.FailAt(next.offset, "CHANNELS in " + where + " declares " + std::to_string(c) +
                                    " channels but lists more names; found an extra " +
                                    Quote(next.text));
      }
      n.num_channels = c;
      n.first_channel = h.total_channels;
      n.has_channels = true;
      h.total_channels += c;
    } else if (EqualsNoCase(k.text, "JOINT") || EqualsNoCase(k.text, "End")) {
      if (!h.nodes[j].has_offset) {
        src.FailAt(k.offset, "expected 'OFFSET x y z' in " + where + " before " + Quote(k.text));
      }
      if (h.nodes[j].end_site) {
        src.FailAt(k.offset, "an End Site cannot have children; expected 'OFFSET' or '}', found " +
                                 Quote(k.text));
      }
      open_node(k, j, EqualsNoCase(k.text, "End"));
    } else if (k.text.empty() || EqualsNoCase(k.text, "MOTION")) {
      src.FailAt(k.offset, "unbalanced braces: " + where + " (opened at line " +
                               std::to_string(src.LineAt(h.nodes[j].decl_offset)) +
                               ") is not closed; expected '}', found " + Describe(k));
    } else {
      src.FailAt(k.offset, "expected OFFSET, CHANNELS, JOINT, End Site or '}' in " + where +
                               ", found " + Describe(k));
    }
  }

  t = tok.Next();
  if (!EqualsNoCase(t.text, "MOTION")) {
    if (t.text == "}") {
      src.FailAt(t.offset, "unbalanced braces: '}' without a matching '{'; expected 'MOTION'");
    }
    if (EqualsNoCase(t.text, "ROOT")) {
      src.FailAt(t.offset, "a second ROOT is not supported; expected 'MOTION' after the hierarchy");
    }
    src.FailAt(t.offset, "expected 'MOTION' after the hierarchy, found " + Describe(t));
  }

  const Token frames = ReadLabelled(tok, src, "Frames", "'Frames: <count>'");
  h.frames_offset = frames.offset;
  {
    const char* b = frames.text.data();
    const char* e = b + frames.text.size();
    const auto r = std::from_chars(b, e, h.num_frames);
    if (frames.text.empty() || r.ec != std::errc() || r.ptr != e || h.num_frames < 0) {
      src.FailAt(frames.offset, "expected a frame count (an integer >= 0) after 'Frames:', found " +
                                    Describe(frames));
    }
  }
  // "Frame Time:" is two words; accept "Time:", "Time: v", "Time:v" and "Time :".
  Token time_value;
  {
    const Token frame_word = tok.Next();
    const Token time_word = tok.Next();
    std::string_view s = time_word.text;
    const bool time_ok = s.size() >= 4 && EqualsNoCase(s.substr(0, 4), "Time");
    if (!EqualsNoCase(frame_word.text, "Frame") || !time_ok) {
      src.FailAt(frame_word.offset, "expected 'Frame Time: <seconds>' after 'Frames:', found " +
                                        Describe(frame_word) + " " + Describe(time_word));
    }
    s.remove_prefix(4);
    if (s.empty()) {
      const Token colon = tok.Next();
      if (colon.text == ":") {
        time_value = tok.Next();
      } else if (!colon.text.empty() && colon.text[0] == ':') {
        time_value = Token{colon.text.substr(1), colon.offset + 1};
      } else {
        src.FailAt(colon.offset, "expected ':' after 'Frame Time', found " + Describe(colon));
      }
    } else if (s[0] == ':') {
      s.remove_prefix(1);
      time_value = s.empty() ? tok.Next() : Token{s, time_word.offset + 5};
    } else {
      src.FailAt(time_word.offset,
                 "expected 'Frame Time: <seconds>', found 'Frame' " + Describe(time_word));
    }
  }
  if (!ParseFiniteDouble(time_value.text, &h.frame_time) || !(h.frame_time > 0) ||
      !std::isfinite(1.0 / h.frame_time)) {
    src.FailAt(time_value.offset,
               "expected a frame time in seconds (a number > 0) after "
               "'Frame Time:', found " +
                   Describe(time_value));
  }
  h.frame_time_token = time_value.text;

  // The rest of the Frame Time line must be empty; frame 0 starts on the next line.
  size_t p = time_value.offset + time_value.text.size();
  const std::string_view text = src.text();
  while (p < text.size() && IsBlank(text[p])) ++p;
  if (p < text.size() && !IsLineEnd(text[p])) {
    size_t e = p;
    while (e < text.size() && !IsSpace(text[e])) ++e;
    src.FailAt(p, "expected the end of the line after the Frame Time, found " +
                      Quote(text.substr(p, e - p)));
  }
  h.data_begin = p;
  return h;
}

// Per-node layout for forward kinematics, resolved once from the header.
struct FkNode {
  int parent;  // node index or -1
  int output;  // output joint index or -1 (End Site not kept)
  int first_channel;
  int num_channels;
  Channel channels[6];
  double offset[3];  // file units
};

// world rotation (row-major 3x3) and translation of every node for one frame; file units.
struct FkScratch {
  std::vector<double> rotation;     // [nodes, 9]
  std::vector<double> translation;  // [nodes, 3]
};

// M <- M * R_axis(angle): right-multiplying by an axis rotation mixes two columns of M.
inline void RotateRight(double* m, int axis, double angle_deg) {
  const double a = angle_deg * kDegToRad;
  const double s = std::sin(a), c = std::cos(a);
  // Columns (u, v) mixed: X -> (1, 2), Y -> (2, 0), Z -> (0, 1); R_axis maps
  // u -> c*u + s*v, v -> -s*u + c*v (column form of the right-handed rotation).
  const int u = axis == 0 ? 1 : (axis == 1 ? 2 : 0);
  const int v = axis == 0 ? 2 : (axis == 1 ? 0 : 1);
  for (int r = 0; r < 3; ++r) {
    const double mu = m[3 * r + u], mv = m[3 * r + v];
    m[3 * r + u] = mu * c + mv * s;
    m[3 * r + v] = -mu * s + mv * c;
  }
}

// World positions of the kept joints for one frame of channel values. out: [J, 3] metres.
void ForwardKinematics(const std::vector<FkNode>& nodes, const double* values, double scale,
                       FkScratch* scratch, float* out) {
  static const double kIdentity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  static const double kZero[3] = {0, 0, 0};
  double* rot = scratch->rotation.data();
  double* tr = scratch->translation.data();
  for (size_t i = 0; i < nodes.size(); ++i) {
    const FkNode& n = nodes[i];
    const double* pr = n.parent >= 0 ? rot + 9 * n.parent : kIdentity;
    const double* pt = n.parent >= 0 ? tr + 3 * n.parent : kZero;
    double* r = rot + 9 * i;
    double* t = tr + 3 * i;
    double local[3] = {n.offset[0], n.offset[1], n.offset[2]};
    for (int k = 0; k < 9; ++k) r[k] = pr[k];
    const double* v = values + n.first_channel;
    for (int c = 0; c < n.num_channels; ++c) {
      const int kind = static_cast<int>(n.channels[c]);
      if (kind < 3) {
        local[kind] = v[c];
      } else {
        RotateRight(r, kind - 3, v[c]);
      }
    }
    // World translation = parent rotation * local translation + parent translation.
    for (int a = 0; a < 3; ++a) {
      t[a] = pr[3 * a] * local[0] + pr[3 * a + 1] * local[1] + pr[3 * a + 2] * local[2] + pt[a];
    }
    if (n.output >= 0) {
      float* o = out + 3 * n.output;
      o[0] = static_cast<float>(t[0] * scale);
      o[1] = static_cast<float>(t[1] * scale);
      o[2] = static_cast<float>(t[2] * scale);
    }
  }
}

// The token starting at p (for messages).
std::string_view TokenAt(std::string_view text, size_t p) {
  size_t e = p;
  while (e < text.size() && !IsSpace(text[e])) ++e;
  return text.substr(p, e - p);
}

// Numbers on the line from p to its end (for the "too many values" message).
int64_t CountTokensToLineEnd(std::string_view text, size_t p) {
  int64_t n = 0;
  while (p < text.size() && !IsLineEnd(text[p])) {
    while (p < text.size() && IsBlank(text[p])) ++p;
    if (p >= text.size() || IsLineEnd(text[p])) break;
    ++n;
    while (p < text.size() && !IsSpace(text[p])) ++p;
  }
  return n;
}

}  // namespace

Motion ReadBvhText(std::string_view text, const std::string& source_name, const BvhOptions& options,
                   BvhRig* rig) {
  if (!(options.scale_to_metres > 0) || !std::isfinite(options.scale_to_metres)) {
    throw std::invalid_argument("BvhOptions::scale_to_metres: expected a finite number > 0, got " +
                                std::to_string(options.scale_to_metres));
  }
  const Source src(text, source_name);
  size_t start = 0;
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") start = 3;  // UTF-8 BOM
  const Header h = ParseHeader(src, start, options);

  // Skeleton and FK layout.
  std::vector<FkNode> fk(h.nodes.size());
  std::vector<std::string> joint_names;
  std::vector<int> parents;
  std::vector<int> output_of(h.nodes.size(), -1);
  for (size_t i = 0; i < h.nodes.size(); ++i) {
    const Node& n = h.nodes[i];
    FkNode& f = fk[i];
    f.parent = n.parent;
    f.first_channel = n.first_channel;
    f.num_channels = n.num_channels;
    std::copy(n.channels, n.channels + 6, f.channels);
    std::copy(n.offset, n.offset + 3, f.offset);
    f.output = -1;
    if (!n.end_site || options.include_end_sites) {
      f.output = static_cast<int>(joint_names.size());
      output_of[i] = f.output;
      joint_names.push_back(n.name);
      // Kept nodes' parents are never End Sites (End Sites have no children).
      parents.push_back(n.parent >= 0 ? output_of[n.parent] : -1);
    }
  }
  const int num_joints = static_cast<int>(joint_names.size());
  const size_t stride = static_cast<size_t>(num_joints) * 3;
  const int num_channels = h.total_channels;
  const int64_t num_frames = h.num_frames;

  if (num_frames > kMaxMotionFrames) {
    src.FailAt(h.frames_offset, "Frames: " + std::to_string(num_frames) +
                                    " is above the limit of " + std::to_string(kMaxMotionFrames) +
                                    " frames per motion");
  }
  if (num_channels == 0 && static_cast<uint64_t>(num_frames) > kMaxRestPoseValues / stride) {
    src.FailAt(h.frames_offset,
               "Frames: " + std::to_string(num_frames) +
                   " frames without channels (no data in the file); expected at most " +
                   std::to_string(kMaxRestPoseValues / stride) + " for " +
                   std::to_string(num_joints) + " joints");
  }
  if (static_cast<uint64_t>(num_frames) > kMaxPositionValues / stride) {
    src.FailAt(h.frames_offset, "Frames: " + std::to_string(num_frames) + " x " +
                                    std::to_string(num_joints) +
                                    " joints is too large; expected at most " +
                                    std::to_string(kMaxPositionValues / 3) + " joint positions");
  }

  std::shared_ptr<const Skeleton> skeleton;
  try {
    std::string skel_name = std::filesystem::path(source_name).stem().string();
    if (skel_name.empty()) skel_name = "bvh";
    skeleton = std::make_shared<const Skeleton>(
        Skeleton::FromParents(std::move(skel_name), std::move(joint_names), std::move(parents)));
  } catch (const std::invalid_argument& e) {
    src.Fail(std::string("invalid hierarchy: ") + e.what());
  }

  const size_t size = text.size();
  size_t p = h.data_begin;
  // Each frame holds num_channels numbers and separators (>= 2 * num_channels - 1 bytes), so the
  // bytes left bound the frames that can exist; never allocate for more than that.
  int64_t storable = num_frames;
  if (num_channels > 0) {
    storable = std::min<int64_t>(
        num_frames,
        static_cast<int64_t>((size - p) / (2 * static_cast<size_t>(num_channels) - 1)) + 1);
  }
  std::vector<float> positions(static_cast<size_t>(storable) * stride);
  std::vector<double> values(static_cast<size_t>(num_channels));
  FkScratch scratch;
  scratch.rotation.resize(9 * fk.size());
  scratch.translation.resize(3 * fk.size());
  const double scale = options.scale_to_metres;
  const char* const data = text.data();
  if (rig) {
    *rig = BvhRig{};
    for (const Node& n : h.nodes) {
      BvhRig::Node r;
      r.name = n.name;
      r.parent = n.parent;
      r.end_site = n.end_site;
      std::copy(n.offset, n.offset + 3, r.offset);
      for (int c = 0; c < n.num_channels; ++c)
        r.channels.push_back(static_cast<int>(n.channels[c]));
      r.first_channel = n.first_channel;
      rig->nodes.push_back(std::move(r));
    }
    rig->num_channels = num_channels;
    rig->frame_time = h.frame_time;
    rig->values.reserve(static_cast<size_t>(storable) * num_channels);
  }

  for (int64_t f = 0; f < num_frames; ++f) {
    // Frame f starts on the next non-blank line (blank lines are skipped).
    while (p < size && IsSpace(data[p])) ++p;
    if (num_channels > 0 && p >= size) {
      src.FailAtFrame(f, size,
                      "the file ends after " + std::to_string(f) + " frames; expected " +
                          std::to_string(num_frames) +
                          " (from 'Frames:'), so it is truncated or "
                          "'Frames:' is wrong");
    }
    for (int c = 0; c < num_channels; ++c) {
      if (c > 0) {
        while (p < size && IsBlank(data[p])) ++p;
        if (p >= size || IsLineEnd(data[p])) {
          src.FailAtFrame(f, p,
                          "expected " + std::to_string(num_channels) + " numbers, found " +
                              std::to_string(c) +
                              (p >= size ? " (the file ends here: truncated?)" : ""));
        }
      }
      const char* b = data + p;
      const char* e = data + size;
      if (*b == '+' && b + 1 < e && (b[1] == '.' || (b[1] >= '0' && b[1] <= '9'))) ++b;
      double v;
      const auto r = std::from_chars(b, e, v);
      if (r.ec != std::errc() || (r.ptr < e && !IsSpace(*r.ptr)) || !std::isfinite(v)) {
        const std::string_view bad = TokenAt(text, p);
        const Node* owner = nullptr;
        for (const Node& n : h.nodes) {
          if (c >= n.first_channel && c < n.first_channel + n.num_channels) owner = &n;
        }
        std::string what = "expected a finite number for value " + std::to_string(c + 1) + " of " +
                           std::to_string(num_channels);
        if (owner) {
          what += " (" + Quote(owner->name) + " " +
                  ChannelName(owner->channels[c - owner->first_channel]) + ")";
        }
        what += ", found " + Quote(bad);
        if (r.ec == std::errc::result_out_of_range) what += " (out of range)";
        src.FailAtFrame(f, p, what);
      }
      values[c] = v;
      p = static_cast<size_t>(r.ptr - data);
    }
    if (num_channels > 0) {
      while (p < size && IsBlank(data[p])) ++p;
      if (p < size && !IsLineEnd(data[p])) {
        src.FailAtFrame(f, p,
                        "too many values on the line: expected " + std::to_string(num_channels) +
                            " numbers, found " +
                            std::to_string(num_channels + CountTokensToLineEnd(text, p)));
      }
    }
    float* out = positions.data() + static_cast<size_t>(f) * stride;
    ForwardKinematics(fk, values.data(), scale, &scratch, out);
    if (rig) rig->values.insert(rig->values.end(), values.begin(), values.end());
    for (size_t i = 0; i < stride; ++i) {
      if (!std::isfinite(out[i])) {
        src.FailAtFrame(f, p,
                        "joint " + Quote(skeleton->joint_name(static_cast<int>(i / 3))) +
                            " has a non-finite position (values too large for 32-bit floats "
                            "in metres); expected positions within +-3.4e38 m");
      }
    }
  }
  while (p < size && IsSpace(data[p])) ++p;
  if (p < size) {
    src.FailAt(p, "found more data after the " + std::to_string(num_frames) +
                      " frames declared by 'Frames:': " + Quote(TokenAt(text, p)) +
                      "; expected the end of the file");
  }

  const double fps = FpsFromFrameTime(h.frame_time, h.frame_time_token);
  if (rig) rig->fps = fps;
  try {
    return Motion(std::move(skeleton), fps, std::move(positions));
  } catch (const std::invalid_argument& e) {
    src.Fail(e.what());
  }
}

Motion ReadBvhFile(const std::string& path, const BvhOptions& options, BvhRig* rig) {
  // A file that does not start with HIERARCHY is refused from its first bytes (the parser's own
  // message), before a large file is read whole.
  const std::string bytes = ReadFileBytes(path, [&](std::string_view head) {
    std::string_view t = head;
    if (t.substr(0, 3) == "\xEF\xBB\xBF") t.remove_prefix(3);
    while (!t.empty() && IsSpace(t.front())) t.remove_prefix(1);
    if (t.size() < 9 || !EqualsNoCase(t.substr(0, 9), "HIERARCHY"))
      ReadBvhText(head, path, options);
  });
  return ReadBvhText(bytes, path, options, rig);
}

}  // namespace motionfork
