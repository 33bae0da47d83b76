#include "io/npy.h"

#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "core/error.h"
#include "io/file_util.h"
#include "io/motion_limits.h"

namespace motionfork {

namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr size_t kMagicLen = 6;
// numpy aligns the data to 64 bytes and leaves room for the first axis to grow to 21 digits.
constexpr size_t kArrayAlign = 64;
constexpr size_t kGrowthAxisMaxDigits = 21;

bool HostIsLittleEndian() {
  const uint16_t probe = 1;
  unsigned char first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

std::string ShapeString(const std::vector<int64_t>& shape) {
  // Python's repr of a tuple: (), (5,), (2, 3).
  std::string s = "(";
  for (size_t i = 0; i < shape.size(); ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(shape[i]);
  }
  if (shape.size() == 1) s += ",";
  return s + ")";
}

// A value of the header dict. Only what .npy headers use: strings, booleans, tuples of
// non-negative integers; anything else (lists for structured dtypes, None, ...) is kept as its
// source text so the error can quote it.
struct HeaderValue {
  enum class Kind { kString, kBool, kIntTuple, kOther } kind = Kind::kOther;
  std::string text;  // string contents, or the raw source of an kOther value
  bool boolean = false;
  std::vector<int64_t> ints;
};

// Recursive-descent parser for the Python dict literal numpy writes (and reasonable hand-written
// variants: any key order, either quote, extra spaces, trailing commas, Python 2 "3L" integers).
class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::string& source) : s_(text), source_(source) {}

  std::vector<std::pair<std::string, HeaderValue>> ParseDict() {
    SkipSpace();
    Expect('{', "'{' opening the header dict");
    std::vector<std::pair<std::string, HeaderValue>> items;
    for (;;) {
      SkipSpace();
      if (Peek() == '}') {
        ++pos_;
        break;
      }
      std::string key = ParseString("a quoted key");
      SkipSpace();
      Expect(':', "':' after the key '" + key + "'");
      SkipSpace();
      HeaderValue value = ParseValue();
      items.emplace_back(std::move(key), std::move(value));
      SkipSpace();
      if (Peek() == ',') {
        ++pos_;
      } else if (Peek() != '}') {
        Fail("',' or '}' in the header dict");
      }
    }
    SkipSpace();
    if (pos_ != s_.size()) Fail("the end of the header after '}'");
    return items;
  }

 private:
  char Peek() const { return pos_ < s_.size() ? s_[pos_] : '\0'; }
  void SkipSpace() {
    while (pos_ < s_.size() &&
           (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\n' || s_[pos_] == '\r')) {
      ++pos_;
    }
  }
  [[noreturn]] void Fail(const std::string& expected) const {
    std::string found = pos_ < s_.size() ? "'" + Printable(s_.substr(pos_, 12)) + "'" : "the end";
    throw FormatError(FormatMessage(
        source_, "npy header",
        "expected " + expected + " at header offset " + std::to_string(pos_) + ", found " + found));
  }
  static std::string Printable(std::string_view s) {
    std::string out;
    for (char c : s) {
      const unsigned char u = static_cast<unsigned char>(c);
      if (u >= 0x20 && u < 0x7f) {
        out += c;
      } else {
        static const char* kHex = "0123456789abcdef";
        out += "\\x";
        out += kHex[u >> 4];
        out += kHex[u & 15];
      }
    }
    return out;
  }
  void Expect(char c, const std::string& what) {
    if (Peek() != c) Fail(what);
    ++pos_;
  }
  std::string ParseString(const std::string& what) {
    const char quote = Peek();
    if (quote != '\'' && quote != '"') Fail(what);
    ++pos_;
    std::string out;
    while (pos_ < s_.size() && s_[pos_] != quote) {
      if (s_[pos_] == '\\') Fail("a string without escapes");
      out += s_[pos_++];
    }
    if (pos_ >= s_.size()) Fail("a closing quote");
    ++pos_;
    return out;
  }
  bool StartsWithWord(std::string_view word) const {
    if (s_.substr(pos_, word.size()) != word) return false;
    const size_t end = pos_ + word.size();
    return end >= s_.size() ||
           !(std::isalnum(static_cast<unsigned char>(s_[end])) || s_[end] == '_');
  }
  HeaderValue ParseValue() {
    HeaderValue v;
    const char c = Peek();
    if (c == '\'' || c == '"') {
      v.kind = HeaderValue::Kind::kString;
      v.text = ParseString("a string");
    } else if (StartsWithWord("True") || StartsWithWord("False")) {
      v.kind = HeaderValue::Kind::kBool;
      v.boolean = StartsWithWord("True");
      pos_ += v.boolean ? 4 : 5;
    } else if (c == '(') {
      v.kind = HeaderValue::Kind::kIntTuple;
      v.ints = ParseIntTuple();
    } else {
      // Skip a balanced value (a list, None, a number) so the caller can say what it found.
      const size_t begin = pos_;
      int depth = 0;
      while (pos_ < s_.size()) {
        const char d = s_[pos_];
        if (d == '[' || d == '(' || d == '{') ++depth;
        if (d == ']' || d == ')' || d == '}') {
          if (depth == 0) break;
          --depth;
        }
        if (d == ',' && depth == 0) break;
        if (d == '\'' || d == '"') {
          ParseString("a string");
          continue;
        }
        ++pos_;
      }
      if (pos_ == begin) Fail("a value");
      v.text = std::string(s_.substr(begin, pos_ - begin));
    }
    return v;
  }
  std::vector<int64_t> ParseIntTuple() {
    Expect('(', "'('");
    std::vector<int64_t> ints;
    for (;;) {
      SkipSpace();
      if (Peek() == ')') {
        ++pos_;
        break;
      }
      if (!std::isdigit(static_cast<unsigned char>(Peek())))
        Fail("a non-negative integer in the shape");
      int64_t value = 0;
      while (std::isdigit(static_cast<unsigned char>(Peek()))) {
        const int digit = Peek() - '0';
        if (value > (std::numeric_limits<int64_t>::max() - digit) / 10) {
          Fail("a shape entry that fits in 64 bits");
        }
        value = value * 10 + digit;
        ++pos_;
      }
      if (Peek() == 'L' || Peek() == 'l') ++pos_;  // Python 2 long literal
      ints.push_back(value);
      SkipSpace();
      if (Peek() == ',') {
        ++pos_;
      } else if (Peek() != ')') {
        Fail("',' or ')' in the shape tuple");
      }
    }
    return ints;
  }

  std::string_view s_;
  const std::string& source_;
  size_t pos_ = 0;
};

struct DType {
  size_t item_size = 0;  // 4 or 8
};

DType ParseDescr(const std::string& descr, const std::string& source) {
  const std::string expected = "expected dtype '<f4' or '<f8' (little-endian float32/float64)";
  auto fail = [&](const std::string& why) -> DType {
    throw FormatError(
        FormatMessage(source, "npy header", expected + ", found '" + descr + "'" + why));
  };
  if (descr.empty()) return fail("");
  char order = '\0';
  std::string rest = descr;
  if (descr[0] == '<' || descr[0] == '>' || descr[0] == '|' || descr[0] == '=') {
    order = descr[0];
    rest = descr.substr(1);
  }
  if (rest.empty()) return fail("");
  const char kind = rest[0];
  const std::string size = rest.substr(1);
  if (kind == 'O') return fail(" (an object array: pickled Python objects are not supported)");
  if (kind != 'f') {
    const std::string what = kind == 'i' || kind == 'u'   ? "an integer array"
                             : kind == 'b'                ? "a boolean array"
                             : kind == 'c'                ? "a complex array"
                             : kind == 'S' || kind == 'U' ? "a string array"
                                                          : "an unsupported dtype";
    return fail(" (" + what + "; convert with arr.astype('<f4'))");
  }
  if (size != "4" && size != "8") {
    return fail(" (" + (size == "2" ? std::string("float16") : "float" + size) +
                " is not supported; convert with arr.astype('<f4'))");
  }
  if (order == '>') return fail(" (big-endian; convert with arr.astype('<f4'))");
  // '=' (native) and '|' (not applicable) and no prefix are what numpy itself reads as native
  // order; numpy never writes them for floats. Take them as little-endian only where native order
  // is little-endian, i.e. where numpy on this machine would read the same numbers.
  if (order != '<' && !HostIsLittleEndian()) {
    return fail(" (byte order ambiguous on this big-endian host)");
  }
  return DType{size == "4" ? size_t{4} : size_t{8}};
}

std::string NonFiniteLocation(const std::vector<int64_t>& shape, size_t index) {
  std::string loc = "flat index " + std::to_string(index);
  if (shape.size() == 3 && shape[2] == 3 && shape[1] > 0) {
    const size_t per_frame = static_cast<size_t>(shape[1]) * 3;
    loc += " (frame " + std::to_string(index / per_frame) + ", joint " +
           std::to_string((index % per_frame) / 3) + ", coordinate " + "xyz"[index % 3] + ")";
  }
  return loc;
}

template <typename T>
T LoadLittleEndian(const char* p) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (!HostIsLittleEndian()) {
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  }
  T value;
  std::memcpy(&value, b, sizeof(T));
  return value;
}

void RequireNpyMagic(std::string_view bytes, const std::string& src) {
  if (bytes.size() < kMagicLen + 2 ||
      bytes.substr(0, kMagicLen) != std::string_view(kMagic, kMagicLen)) {
    throw FormatError(FormatMessage(
        src, "", "not a NumPy .npy file: expected the magic bytes \\x93NUMPY at the start"));
  }
}

}  // namespace

NpyArray ParseNpy(std::string_view bytes, const std::string& source_name, bool allow_nan) {
  const std::string& src = source_name;
  RequireNpyMagic(bytes, src);
  const int major = static_cast<unsigned char>(bytes[6]);
  const int minor = static_cast<unsigned char>(bytes[7]);
  if ((major != 1 && major != 2 && major != 3) || minor != 0) {
    throw FormatError(FormatMessage(src, "",
                                    "unsupported .npy format version " + std::to_string(major) +
                                        "." + std::to_string(minor) +
                                        " (expected 1.0, 2.0 or 3.0)"));
  }
  const size_t len_size = major == 1 ? 2 : 4;
  const size_t prefix = kMagicLen + 2 + len_size;
  if (bytes.size() < prefix) {
    throw FormatError(FormatMessage(src, "",
                                    "truncated .npy file: expected at least " +
                                        std::to_string(prefix) + " bytes, found " +
                                        std::to_string(bytes.size())));
  }
  size_t header_len = 0;
  for (size_t i = 0; i < len_size; ++i) {
    header_len |= static_cast<size_t>(static_cast<unsigned char>(bytes[8 + i])) << (8 * i);
  }
  if (bytes.size() - prefix < header_len) {
    throw FormatError(FormatMessage(src, "npy header",
                                    "truncated header: expected " + std::to_string(header_len) +
                                        " header bytes, found " +
                                        std::to_string(bytes.size() - prefix)));
  }
  const std::string_view header = bytes.substr(prefix, header_len);
  const auto items = HeaderParser(header, src).ParseDict();

  const HeaderValue* descr = nullptr;
  const HeaderValue* fortran = nullptr;
  const HeaderValue* shape = nullptr;
  for (const auto& [key, value] : items) {
    const HeaderValue** slot = key == "descr"           ? &descr
                               : key == "fortran_order" ? &fortran
                               : key == "shape"         ? &shape
                                                        : nullptr;
    if (!slot) continue;  // numpy writes no other keys; tolerate extras
    if (*slot) {
      throw FormatError(FormatMessage(src, "npy header", "duplicate key '" + key + "'"));
    }
    *slot = &value;
  }
  for (const auto& [name, value] : {std::pair<const char*, const HeaderValue*>{"descr", descr},
                                    {"fortran_order", fortran},
                                    {"shape", shape}}) {
    if (!value) {
      throw FormatError(FormatMessage(
          src, "npy header",
          std::string("expected the key '") + name + "' in the header dict, found none"));
    }
  }
  if (descr->kind != HeaderValue::Kind::kString) {
    throw FormatError(
        FormatMessage(src, "npy header",
                      "expected dtype '<f4' or '<f8' (a plain float array), found descr " +
                          (descr->text.empty() ? std::string("of another kind") : descr->text) +
                          " (a structured dtype?)"));
  }
  const DType dtype = ParseDescr(descr->text, src);
  if (fortran->kind != HeaderValue::Kind::kBool) {
    throw FormatError(FormatMessage(
        src, "npy header", "expected fortran_order True or False, found " + fortran->text));
  }
  if (fortran->boolean) {
    throw FormatError(FormatMessage(
        src, "npy header",
        "expected fortran_order False (C order), found True; save np.ascontiguousarray(arr)"));
  }
  if (shape->kind != HeaderValue::Kind::kIntTuple) {
    throw FormatError(FormatMessage(src, "npy header",
                                    "expected a shape tuple of integers, found " + shape->text));
  }

  NpyArray out;
  out.shape = shape->ints;
  // Element count with overflow checks: a corrupt shape must not make us allocate terabytes.
  const size_t data_bytes = bytes.size() - prefix - header_len;
  bool has_zero = false;
  for (int64_t d : out.shape) has_zero = has_zero || d == 0;
  size_t count = has_zero ? 0 : 1;
  bool overflow = false;
  for (int64_t d : out.shape) {
    if (has_zero) break;
    if (count > std::numeric_limits<size_t>::max() / dtype.item_size / static_cast<size_t>(d)) {
      overflow = true;
      break;
    }
    count *= static_cast<size_t>(d);
  }
  const std::string type_name = dtype.item_size == 4 ? "float32" : "float64";
  if (overflow || count * dtype.item_size != data_bytes) {
    const std::string expected =
        overflow ? std::string("more than 2^64") : std::to_string(count * dtype.item_size);
    const std::string what = !overflow && data_bytes > count * dtype.item_size
                                 ? "unexpected trailing data"
                                 : "truncated data";
    throw FormatError(FormatMessage(src, "",
                                    what + ": expected " + expected + " bytes of data for shape " +
                                        ShapeString(out.shape) + " " + type_name + ", found " +
                                        std::to_string(data_bytes)));
  }

  const char* data = bytes.data() + prefix + header_len;
  out.data.resize(count);
  for (size_t i = 0; i < count; ++i) {
    float v;
    if (dtype.item_size == 4) {
      v = LoadLittleEndian<float>(data + 4 * i);
    } else {
      const double d = LoadLittleEndian<double>(data + 8 * i);
      if (std::isfinite(d) && std::fabs(d) > std::numeric_limits<float>::max()) {
        throw FormatError(FormatMessage(src, "",
                                        "value " + std::to_string(d) + " at " +
                                            NonFiniteLocation(out.shape, i) +
                                            " is outside the float32 range"));
      }
      v = static_cast<float>(d);
    }
    if (!std::isfinite(v) && !(allow_nan && std::isnan(v))) {
      throw FormatError(FormatMessage(src, "",
                                      std::string("expected finite values, found ") +
                                          (std::isnan(v) ? "NaN" : "Inf") + " at " +
                                          NonFiniteLocation(out.shape, i)));
    }
    out.data[i] = v;
  }
  return out;
}

NpyArray ReadNpy(const std::string& path, bool allow_nan) {
  const std::string bytes =
      ReadFileBytes(path, [&path](std::string_view head) { RequireNpyMagic(head, path); });
  return ParseNpy(bytes, path, allow_nan);
}

std::string SerializeNpy(const NpyArray& array) {
  size_t count = 1;
  for (int64_t d : array.shape) {
    if (d < 0) {
      throw std::invalid_argument("SerializeNpy: expected non-negative dimensions, got shape " +
                                  ShapeString(array.shape));
    }
    count *= static_cast<size_t>(d);
  }
  if (count != array.data.size()) {
    throw std::invalid_argument("SerializeNpy: shape " + ShapeString(array.shape) + " expects " +
                                std::to_string(count) + " values, got " +
                                std::to_string(array.data.size()));
  }
  for (size_t i = 0; i < array.data.size(); ++i) {
    if (!std::isfinite(array.data[i])) {
      // Our reader rejects non-finite values, so writing one would make an unreadable file.
      throw std::invalid_argument("SerializeNpy: expected finite values, got " +
                                  std::to_string(array.data[i]) + " at " +
                                  NonFiniteLocation(array.shape, i));
    }
  }
  // Exactly what numpy (>= 1.23) np.save writes for a C-order '<f4' array.
  std::string dict =
      "{'descr': '<f4', 'fortran_order': False, 'shape': " + ShapeString(array.shape) + ", }";
  if (!array.shape.empty()) {
    const size_t digits = std::to_string(array.shape[0]).size();
    dict.append(digits < kGrowthAxisMaxDigits ? kGrowthAxisMaxDigits - digits : 0, ' ');
  }
  size_t hlen = dict.size() + 1;  // + the final newline
  int major = 1;
  size_t len_size = 2;
  size_t pad = kArrayAlign - (kMagicLen + 2 + len_size + hlen) % kArrayAlign;
  if (hlen + pad > 0xffff) {
    major = 2;
    len_size = 4;
    pad = kArrayAlign - (kMagicLen + 2 + len_size + hlen) % kArrayAlign;
  }
  const size_t header_len = hlen + pad;
  std::string out(kMagic, kMagicLen);
  out += static_cast<char>(major);
  out += '\0';
  for (size_t i = 0; i < len_size; ++i) out += static_cast<char>((header_len >> (8 * i)) & 0xff);
  out += dict;
  out.append(pad, ' ');
  out += '\n';
  const size_t data_begin = out.size();
  out.resize(data_begin + 4 * array.data.size());
  for (size_t i = 0; i < array.data.size(); ++i) {
    unsigned char b[4];
    std::memcpy(b, &array.data[i], 4);
    if (!HostIsLittleEndian()) {
      std::swap(b[0], b[3]);
      std::swap(b[1], b[2]);
    }
    std::memcpy(&out[data_begin + 4 * i], b, 4);
  }
  return out;
}

void WriteNpy(const std::string& path, const NpyArray& array) {
  WriteFileAtomically(path, SerializeNpy(array));
}

Motion ReadNpyMotion(const std::string& path, std::shared_ptr<const Skeleton> skeleton, double fps,
                     std::vector<uint8_t>* missing) {
  NpyArray array = ReadNpy(path, missing != nullptr);
  if (array.shape.size() != 3 || array.shape[2] != 3) {
    throw FormatError(FormatMessage(
        path, "",
        "expected positions of shape [T, J, 3], found shape " + ShapeString(array.shape)));
  }
  const int64_t frames = array.shape[0], joints = array.shape[1];
  if (frames < 1 || joints < 1) {
    throw FormatError(FormatMessage(
        path, "",
        "expected at least 1 frame and 1 joint, found shape " + ShapeString(array.shape)));
  }
  if (frames > kMaxMotionFrames || joints > kMaxMotionJoints) {
    throw FormatError(FormatMessage(path, "",
                                    "shape " + ShapeString(array.shape) +
                                        " is above the limits of " +
                                        std::to_string(kMaxMotionFrames) + " frames and " +
                                        std::to_string(kMaxMotionJoints) + " joints per motion"));
  }
  if (!skeleton) {
    skeleton = std::make_shared<const Skeleton>(Skeleton::Anonymous(static_cast<int>(joints)));
  } else if (skeleton->num_joints() != joints) {
    throw FormatError(FormatMessage(path, "",
                                    "expected " + std::to_string(skeleton->num_joints()) +
                                        " joints (skeleton '" + skeleton->name() +
                                        "'), found shape " + ShapeString(array.shape)));
  }
  if (missing) {
    missing->assign(array.data.size(), 0);
    for (size_t i = 0; i < array.data.size(); ++i) {
      if (std::isnan(array.data[i])) {
        (*missing)[i] = 1;
        array.data[i] = 0.0f;
      }
    }
  }
  return Motion(std::move(skeleton), fps, std::move(array.data));
}

void WriteNpyMotion(const std::string& path, const Motion& motion) {
  NpyArray array;
  array.shape = {motion.num_frames(), motion.num_joints(), 3};
  array.data = motion.positions();
  WriteNpy(path, array);
}

}  // namespace motionfork
