#include "config/constraint_config.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "config/yaml_util.h"
#include "core/error.h"

namespace motionfork {

using yaml_util::Fail;

namespace {

const char* const kTopKeys[] = {"name", "skeleton", "sides", "vectors", "constraints", "rigid"};
const char* const kConstraintKeys[] = {"name", "per_side", "a", "b", "range", "anatomical", "note"};

template <size_t N>
bool Known(const char* const (&keys)[N], const std::string& key) {
  for (const char* k : keys) {
    if (key == k) return true;
  }
  return false;
}

template <size_t N>
std::string KeyList(const char* const (&keys)[N]) {
  std::string out;
  for (const char* k : keys) out += (out.empty() ? "" : ", ") + std::string(k);
  return out;
}

// ---- Expression parsing -------------------------------------------------------------------

// Recursive descent over "kind(arg, arg)" with named-vector references. Errors are
// std::invalid_argument with a column; the YAML layer adds file, line and constraint.
class ExpressionParser {
 public:
  // named: vector name -> text; resolved on use (recursively, cycles reported).
  ExpressionParser(const std::map<std::string, std::string>* named, std::set<std::string>* stack)
      : named_(named), stack_(stack) {}

  VectorExpr Parse(const std::string& text) {
    text_ = text;
    pos_ = 0;
    VectorExpr e = Expr();
    SkipSpace();
    if (pos_ != text_.size()) Error("unexpected '" + text_.substr(pos_) + "' after the expression");
    return e;
  }

 private:
  [[noreturn]] void Error(const std::string& what) const {
    throw std::invalid_argument(what + " (column " + std::to_string(pos_ + 1) + " of '" + text_ +
                                "')");
  }
  void SkipSpace() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool Peek(char c) {
    SkipSpace();
    return pos_ < text_.size() && text_[pos_] == c;
  }
  void Expect(char c, const std::string& what) {
    if (!Peek(c)) {
      Error("expected '" + std::string(1, c) + "' " + what + ", found " +
            (pos_ < text_.size() ? "'" + text_.substr(pos_, 1) + "'" : "the end"));
    }
    ++pos_;
  }
  std::string Identifier() {
    SkipSpace();
    const size_t start = pos_;
    while (pos_ < text_.size() &&
           (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) {
      ++pos_;
    }
    if (pos_ == start) {
      Error("expected bone(a, b), normal(u, v) or a named vector, found " +
            (pos_ < text_.size() ? "'" + text_.substr(pos_) + "'" : "nothing"));
    }
    return text_.substr(start, pos_ - start);
  }
  // A joint name: everything up to ',' or ')', trimmed. Placeholders {side}/{other} only.
  std::string JointName() {
    SkipSpace();
    const size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != ',' && text_[pos_] != ')' && text_[pos_] != '(') {
      ++pos_;
    }
    std::string name = text_.substr(start, pos_ - start);
    while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
    if (name.empty()) {
      pos_ = start;
      Error("expected a joint name");
    }
    for (size_t open = name.find('{'); open != std::string::npos; open = name.find('{', open + 1)) {
      const size_t close = name.find('}', open);
      const std::string ph =
          close == std::string::npos ? name.substr(open) : name.substr(open, close - open + 1);
      if (ph != "{side}" && ph != "{other}") {
        pos_ = start;
        Error("unknown placeholder '" + ph + "' in joint name '" + name +
              "' (known: {side}, {other})");
      }
    }
    return name;
  }
  VectorExpr Expr() {
    const size_t start = pos_;
    const std::string id = Identifier();
    if (!Peek('(')) {
      if (named_ && named_->count(id)) return Named(id);
      pos_ = start;
      std::string known;
      if (named_) {
        for (const auto& kv : *named_) known += (known.empty() ? "" : ", ") + kv.first;
      }
      Error("unknown vector '" + id + "' (expected bone(a, b), normal(u, v)" +
            (known.empty() ? std::string("") : " or a named vector: " + known) + ")");
    }
    ++pos_;  // '('
    if (id == "bone") {
      const std::string from = JointName();
      Expect(',', "between the two joints of bone(a, b)");
      const std::string to = JointName();
      Expect(')', "closing bone(a, b)");
      return VectorExpr::Bone(from, to);
    }
    if (id == "normal") {
      VectorExpr u = Expr();
      Expect(',', "between the two vectors of normal(u, v)");
      VectorExpr v = Expr();
      Expect(')', "closing normal(u, v)");
      return VectorExpr::Normal(std::move(u), std::move(v));
    }
    pos_ = start;
    Error("unknown vector kind '" + id + "' (known: bone(a, b), normal(u, v))");
  }
  VectorExpr Named(const std::string& id) {
    if (stack_->count(id)) Error("named vector '" + id + "' refers to itself");
    stack_->insert(id);
    ExpressionParser inner(named_, stack_);
    VectorExpr e;
    try {
      e = inner.Parse(named_->at(id));
    } catch (const std::invalid_argument& err) {
      stack_->erase(id);
      throw std::invalid_argument("in named vector '" + id + "': " + err.what());
    }
    stack_->erase(id);
    return e;
  }

  const std::map<std::string, std::string>* named_;
  std::set<std::string>* stack_;
  std::string text_;
  size_t pos_ = 0;
};

bool HasPlaceholder(const std::string& text) {
  return text.find("{side}") != std::string::npos || text.find("{other}") != std::string::npos;
}

std::string Scalar(const YAML::Node& n) {
  return n.IsScalar() ? n.as<std::string>() : std::string();
}

// A [lower, upper] pair of degrees (`range`, `anatomical`): numbers in [0, 180], lower <= upper.
void ParseDegrees(const std::string& file, const YAML::Node& node, const std::string& who,
                  const std::string& key, double* lower, double* upper) {
  if (!node.IsSequence() || node.size() != 2) {
    Fail(file, node,
         who + "'" + key + "' must be [lower, upper] in degrees, found " + YAML::Dump(node));
  }
  double bound[2];
  for (int k = 0; k < 2; ++k) {
    try {
      bound[k] = node[k].as<double>();
    } catch (const YAML::Exception&) {
      Fail(file, node[k], who + key + " bound '" + YAML::Dump(node[k]) + "' is not a number");
    }
    if (!std::isfinite(bound[k]) || bound[k] < 0 || bound[k] > 180) {
      Fail(file, node[k],
           who + key + " bound " + YAML::Dump(node[k]) + " is outside [0, 180] degrees");
    }
  }
  if (bound[0] > bound[1]) {
    Fail(file, node,
         who + key + ": lower bound " + YAML::Dump(node[0]) + " > upper bound " +
             YAML::Dump(node[1]));
  }
  *lower = bound[0];
  *upper = bound[1];
}

ConstraintSetSpec ParseRoot(const YAML::Node& root, const std::string& file,
                            const ConstraintLoadOptions& options) {
  ConstraintSetSpec spec;
  spec.source = file;
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (!Known(kTopKeys, key)) {
      Fail(file, kv.first, "unknown key '" + key + "' (known: " + KeyList(kTopKeys) + ")");
    }
  }
  spec.name = yaml_util::Get<std::string>(file, root, "name");
  spec.skeleton = yaml_util::GetOr<std::string>(file, root, "skeleton", "");
  if (const YAML::Node sides = root["sides"]) {
    if (!sides.IsSequence() || sides.size() != 2 || !sides[0].IsScalar() || !sides[1].IsScalar()) {
      Fail(file, sides, "'sides' must be [left token, right token], e.g. [L, R]");
    }
    spec.left_token = sides[0].as<std::string>();
    spec.right_token = sides[1].as<std::string>();
    if (spec.left_token.empty() || spec.left_token == spec.right_token) {
      Fail(file, sides, "'sides' needs two different, non-empty tokens");
    }
  }

  if (const YAML::Node rigid = root["rigid"]) {
    if (!rigid.IsSequence())
      Fail(file, rigid, "'rigid' must be a list of joint lists, e.g. [[LHip, RHip, Spine]]");
    for (const YAML::Node& group : rigid) {
      if (!group.IsSequence() || group.size() < 1) {
        Fail(file, group, "each 'rigid' entry must be a non-empty list of joint names");
      }
      std::vector<std::string> joints;
      for (const YAML::Node& j : group) {
        if (!j.IsScalar()) Fail(file, j, "a 'rigid' joint must be a joint name");
        joints.push_back(j.as<std::string>());
      }
      spec.rigid.push_back(std::move(joints));
    }
  }

  std::map<std::string, std::string> named;
  if (const YAML::Node vectors = root["vectors"]) {
    if (!vectors.IsMap()) Fail(file, vectors, "'vectors' must map a name to an expression");
    for (const auto& kv : vectors) {
      const std::string name = kv.first.as<std::string>();
      if (name == "bone" || name == "normal") {
        Fail(file, kv.first, "a named vector cannot be called '" + name + "'");
      }
      for (char c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') {
          Fail(file, kv.first, "named vector '" + name + "': use letters, digits and '_' only");
        }
      }
      if (!kv.second.IsScalar()) Fail(file, kv.second, "named vector '" + name + "' must be text");
      spec.vectors.emplace_back(name, kv.second.as<std::string>());
      named[name] = kv.second.as<std::string>();
    }
    // Parse each once so a broken named vector is reported even when unused.
    for (const auto& kv : vectors) {
      const std::string name = kv.first.as<std::string>();
      std::set<std::string> stack{name};
      try {
        ExpressionParser(&named, &stack).Parse(named[name]);
      } catch (const std::invalid_argument& e) {
        Fail(file, kv.second, "named vector '" + name + "': " + e.what());
      }
    }
  }

  const YAML::Node list = root["constraints"];
  if (!list || !list.IsSequence() || list.size() == 0) {
    Fail(file, list ? list : root, "expected a non-empty list 'constraints'");
  }
  std::set<std::string> names;
  for (const YAML::Node& n : list) {
    if (!n.IsMap()) Fail(file, n, "each constraint must be a mapping with name, a, b and range");
    ConstraintSpec c;
    c.location = yaml_util::Where(n);
    if (!n["name"] || !n["name"].IsScalar() || n["name"].as<std::string>().empty()) {
      Fail(file, n, "a constraint has no 'name'");
    }
    c.name = n["name"].as<std::string>();
    const std::string who = "constraint '" + c.name + "': ";
    for (const auto& kv : n) {
      const std::string key = kv.first.as<std::string>();
      if (!Known(kConstraintKeys, key)) {
        Fail(file, kv.first,
             who + "unknown key '" + key + "' (known: " + KeyList(kConstraintKeys) + ")");
      }
    }
    if (!names.insert(c.name).second) Fail(file, n, who + "the name is used twice");
    c.per_side = yaml_util::GetOr<bool>(file, n, "per_side", false);
    c.note = yaml_util::GetOr<std::string>(file, n, "note", "");
    for (const char* key : {"a", "b"}) {
      const YAML::Node e = n[key];
      if (!e) Fail(file, n, who + "missing vector '" + key + "'");
      const std::string text = Scalar(e);
      if (text.empty())
        Fail(file, e, who + "'" + key + "' must be an expression such as bone(a, b)");
      if (!c.per_side && HasPlaceholder(text)) {
        Fail(file, e,
             who + "'" + key +
                 "' uses {side}/{other} but the constraint is not per-side "
                 "(add 'per_side: true')");
      }
      std::set<std::string> stack;
      try {
        VectorExpr parsed = ExpressionParser(&named, &stack).Parse(text);
        (key[0] == 'a' ? c.a : c.b) = std::move(parsed);
        (key[0] == 'a' ? c.a_text : c.b_text) = text;
      } catch (const std::invalid_argument& err) {
        Fail(file, e, who + "vector '" + key + "': " + err.what());
      }
    }
    const YAML::Node range = n["range"];
    if (!range) {
      if (options.require_ranges) {
        Fail(file, n, who + "missing 'range: [lower, upper]' (degrees)");
      }
    } else {
      ParseDegrees(file, range, who, "range", &c.lower_deg, &c.upper_deg);
      c.has_range = true;
    }
    if (const YAML::Node limit = n["anatomical"]) {
      ParseDegrees(file, limit, who, "anatomical", &c.anatomical_lower_deg,
                   &c.anatomical_upper_deg);
      c.has_anatomical = true;
    }
    spec.constraints.push_back(std::move(c));
  }
  // The per-side twins' names must not collide with other constraints.
  for (const ConstraintSpec& c : spec.constraints) {
    if (!c.per_side) continue;
    for (const std::string& tok : {spec.left_token, spec.right_token}) {
      if (names.count(c.name + "_" + tok)) {
        throw FormatError(FormatMessage(file, c.location,
                                        "constraint '" + c.name + "': its side instance '" +
                                            c.name + "_" + tok +
                                            "' clashes with another constraint"));
      }
    }
  }
  return spec;
}

// Plain YAML scalar when safe, else double-quoted.
std::string YamlString(const std::string& s) {
  bool plain = !s.empty();
  for (char c : s) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) ||
          std::string("_(){}, .+-/").find(c) != std::string::npos)) {
      plain = false;
    }
  }
  if (plain &&
      (s.front() == '{' || s.front() == ' ' || s.back() == ' ' || s.front() == '-' || s == "true" ||
       s == "false" || s == "null" || s == "~" || s == "yes" || s == "no")) {
    plain = false;
  }
  if (plain) {
    // Numbers would read back as numbers; keep names as names.
    char* end = nullptr;
    std::strtod(s.c_str(), &end);
    if (end && *end == '\0') plain = false;
  }
  if (plain) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.10g", v);
  return buf;
}

}  // namespace

VectorExpr ParseVectorExpression(const std::string& text) {
  std::set<std::string> stack;
  return ExpressionParser(nullptr, &stack).Parse(text);
}

ConstraintSetSpec ParseConstraintConfig(const std::string& yaml_text,
                                        const std::string& source_name,
                                        const ConstraintLoadOptions& options) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw yaml_util::YamlError(source_name, e);
  }
  if (!root.IsMap()) {
    throw FormatError(FormatMessage(source_name, "", "expected a YAML mapping at the top level"));
  }
  try {
    return ParseRoot(root, source_name, options);
  } catch (const YAML::Exception& e) {
    throw yaml_util::YamlError(source_name, e);
  }
}

ConstraintSetSpec LoadConstraintConfig(const std::string& path,
                                       const ConstraintLoadOptions& options) {
  const YAML::Node root = yaml_util::LoadFile(path);
  try {
    return ParseRoot(root, path, options);
  } catch (const YAML::Exception& e) {
    throw yaml_util::YamlError(path, e);
  }
}

std::string FormatConstraintConfig(const ConstraintSetSpec& spec,
                                   const std::string& header_comment) {
  std::ostringstream out;
  std::istringstream header(header_comment);
  for (std::string line; std::getline(header, line);) {
    out << (line.empty() ? "#" : "# " + line) << "\n";
  }
  out << "name: " << YamlString(spec.name) << "\n";
  if (!spec.skeleton.empty()) out << "skeleton: " << YamlString(spec.skeleton) << "\n";
  out << "sides: [" << YamlString(spec.left_token) << ", " << YamlString(spec.right_token) << "]\n";
  if (!spec.vectors.empty()) {
    out << "vectors:\n";
    for (const auto& [name, text] : spec.vectors)
      out << "  " << name << ": " << YamlString(text) << "\n";
  }
  if (!spec.rigid.empty()) {
    out << "rigid:\n";
    for (const std::vector<std::string>& group : spec.rigid) {
      out << "  - [";
      for (size_t i = 0; i < group.size(); ++i) out << (i ? ", " : "") << YamlString(group[i]);
      out << "]\n";
    }
  }
  out << "constraints:\n";
  for (const ConstraintSpec& c : spec.constraints) {
    out << "  - name: " << YamlString(c.name) << "\n";
    if (c.per_side) out << "    per_side: true\n";
    out << "    a: " << YamlString(c.a_text) << "\n";
    out << "    b: " << YamlString(c.b_text) << "\n";
    if (c.has_range) {
      out << "    range: [" << Number(c.lower_deg) << ", " << Number(c.upper_deg) << "]";
      if (!c.range_comment.empty()) out << "  # " << c.range_comment;
      out << "\n";
    }
    if (c.has_anatomical) {
      out << "    anatomical: [" << Number(c.anatomical_lower_deg) << ", "
          << Number(c.anatomical_upper_deg) << "]\n";
    }
    if (!c.note.empty()) out << "    note: " << YamlString(c.note) << "\n";
  }
  return out.str();
}

}  // namespace motionfork
