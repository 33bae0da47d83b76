// BVH reader: forward kinematics against hand-derived numbers and an independent Eigen FK,
// channel layouts (CMU, Bandai), line endings, error messages, and every clip of the Bandai
// archives.
#include "io/bvh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/archive.h"
#include "test_support.h"

namespace motionfork {
namespace {

// ---------------------------------------------------------------------------------------------
// A BVH described in code: joints in file order (parent before child, depth-first), channels per
// joint, and frames of channel values. Written out as text, and evaluated by a reference FK that
// shares no code with the reader.
struct SpecJoint {
  std::string name;
  int parent;  // -1 for the root
  Eigen::Vector3d offset;
  std::vector<std::string> channels;
  bool end_site = false;
};

struct Spec {
  std::vector<SpecJoint> joints;
  std::vector<std::vector<double>> frames;  // [T, channels]
  std::string frame_time = "0.0333333";
};

void WriteJoint(const Spec& s, int j, int depth, std::ostringstream& out) {
  const std::string ind(2 * depth, ' ');
  const SpecJoint& jt = s.joints[j];
  if (jt.end_site) {
    out << ind << "End Site\n";
  } else {
    out << ind << (jt.parent < 0 ? "ROOT " : "JOINT ") << jt.name << "\n";
  }
  out << ind << "{\n";
  out.precision(9);
  out << ind << "  OFFSET " << jt.offset.x() << " " << jt.offset.y() << " " << jt.offset.z()
      << "\n";
  if (!jt.end_site) {
    out << ind << "  CHANNELS " << jt.channels.size();
    for (const auto& c : jt.channels) out << " " << c;
    out << "\n";
  }
  for (int k = 0; k < static_cast<int>(s.joints.size()); ++k) {
    if (s.joints[k].parent == j) WriteJoint(s, k, depth + 1, out);
  }
  out << ind << "}\n";
}

std::string WriteBvh(const Spec& s) {
  std::ostringstream out;
  out << "HIERARCHY\n";
  WriteJoint(s, 0, 0, out);
  out << "MOTION\nFrames: " << s.frames.size() << "\nFrame Time: " << s.frame_time << "\n";
  out.precision(9);
  for (const auto& f : s.frames) {
    for (size_t i = 0; i < f.size(); ++i) out << (i ? " " : "") << f[i];
    out << "\n";
  }
  return out.str();
}

// Channel values are consumed in the order the joints are written (depth-first), which for a
// spec listed in file order is the spec order.
int TotalChannels(const Spec& s) {
  int n = 0;
  for (const auto& j : s.joints) n += static_cast<int>(j.channels.size());
  return n;
}

// Reference FK with Eigen transforms: local = [R | t], R = product of axis rotations in listed
// order, t = OFFSET with position channels substituted. Returns [J, 3] in file units for the
// joints kept (End Sites only when include_end_sites).
std::vector<Eigen::Vector3d> ReferenceFk(const Spec& s, const std::vector<double>& values,
                                         bool include_end_sites) {
  std::vector<Eigen::Isometry3d> world(s.joints.size());
  std::vector<Eigen::Vector3d> out;
  size_t v = 0;
  for (size_t j = 0; j < s.joints.size(); ++j) {
    const SpecJoint& jt = s.joints[j];
    Eigen::Vector3d t = jt.offset;
    Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
    for (const auto& c : jt.channels) {
      const double x = values.at(v++);
      const int axis = c[0] - 'X';
      if (c.find("position") != std::string::npos) {
        t[axis] = x;
      } else {
        r = r * Eigen::AngleAxisd(x * M_PI / 180.0, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
      }
    }
    Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
    local.linear() = r;
    local.translation() = t;
    world[j] = jt.parent < 0 ? local : world[jt.parent] * local;
    if (!jt.end_site || include_end_sites) out.push_back(world[j].translation());
  }
  return out;
}

void CheckAgainstReference(const Motion& m, const Spec& s, bool include_end_sites, double scale,
                           double tolerance_m = 1e-5) {
  REQUIRE(m.num_frames() == static_cast<int>(s.frames.size()));
  for (int t = 0; t < m.num_frames(); ++t) {
    const auto ref = ReferenceFk(s, s.frames[t], include_end_sites);
    REQUIRE(m.num_joints() == static_cast<int>(ref.size()));
    for (int j = 0; j < m.num_joints(); ++j) {
      for (int a = 0; a < 3; ++a) {
        INFO("frame " << t << " joint " << m.skeleton().joint_name(j) << " axis " << a);
        CHECK(std::abs(m.at(t, j)[a] - ref[j][a] * scale) < tolerance_m);
      }
    }
  }
}

std::string ToCrlf(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\n') out += '\r';
    out += c;
  }
  return out;
}

// A small humanoid with End Sites on the leaves; channels chosen per joint by `channels_for`.
Spec MakeHumanoidSpec(const std::function<std::vector<std::string>(int)>& channels_for) {
  Spec s;
  auto add = [&](const std::string& name, int parent, Eigen::Vector3d off) {
    const int idx = static_cast<int>(s.joints.size());
    s.joints.push_back({name, parent, off, channels_for(idx), false});
    return idx;
  };
  auto end = [&](int parent, Eigen::Vector3d off) {
    s.joints.push_back({"", parent, off, {}, true});
  };
  const int hips = add("Hips", -1, {0, 93, 0});
  const int spine = add("Spine", hips, {0, 10, -1});
  const int chest = add("Chest", spine, {0, 15, 0.5});
  const int neck = add("Neck", chest, {0, 16, 0});
  const int head = add("Head", neck, {0, 8, 1});
  end(head, {0, 12, 0});
  const int arm_l = add("UpperArm_L", chest, {15, 10, 0});
  const int fore_l = add("LowerArm_L", arm_l, {26, 0, 0});
  end(fore_l, {24, 0, 0});
  const int leg_r = add("UpperLeg_R", hips, {-9, -5, 0});
  const int knee_r = add("LowerLeg_R", leg_r, {0, -42, 0});
  const int foot_r = add("Foot_R", knee_r, {0, -41, 0});
  end(foot_r, {0, -5, 12});
  return s;
}

void AddRandomFrames(Spec* s, int frames, unsigned seed, double pos_range, double angle_range) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ang(-angle_range, angle_range);
  std::uniform_real_distribution<double> pos(-pos_range, pos_range);
  for (int t = 0; t < frames; ++t) {
    std::vector<double> f;
    for (const auto& j : s->joints) {
      for (const auto& c : j.channels) {
        f.push_back(c.find("position") != std::string::npos ? pos(rng) : ang(rng));
      }
    }
    s->frames.push_back(f);
  }
}

// ---------------------------------------------------------------------------------------------

// Root at the origin with 6 channels; A (Z X Y), B (X Y Z), End Site below B. Expected world
// positions derived by hand with Rz(90): x->y, y->-x and Rx(90): y->z, z->-y.
const char kHandBvh[] =
    "HIERARCHY\n"
    "ROOT Root\n"
    "{\n"
    "  OFFSET 0 0 0\n"
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    "  JOINT A\n"
    "  {\n"
    "    OFFSET 10 0 0\n"
    "    CHANNELS 3 Zrotation Xrotation Yrotation\n"
    "    JOINT B\n"
    "    {\n"
    "      OFFSET 0 20 0\n"
    "      CHANNELS 3 Xrotation Yrotation Zrotation\n"
    "      End Site\n"
    "      {\n"
    "        OFFSET 0 0 5\n"
    "      }\n"
    "    }\n"
    "  }\n"
    "}\n"
    "MOTION\n"
    "Frames: 4\n"
    "Frame Time: 0.04\n"
    "0 0 0 0 0 0 0 0 0 0 0 0\n"
    "100 0 0 90 0 0 0 0 0 0 0 0\n"
    "0 0 0 0 0 0 90 90 0 0 0 0\n"
    "0 50 0 0 0 0 0 0 0 90 0 0\n";

TEST_CASE("bvh: hand-derived world positions with 90-degree rotations", "[io][bvh]") {
  BvhOptions opt;
  opt.include_end_sites = true;
  const Motion m = ReadBvhText(kHandBvh, "hand.bvh", opt);
  REQUIRE(m.num_joints() == 4);
  REQUIRE(m.num_frames() == 4);
  CHECK(m.fps() == 25.0);
  CHECK(m.skeleton().joint_names() == std::vector<std::string>{"Root", "A", "B", "B_End"});
  CHECK(m.skeleton().parents() == std::vector<int>{-1, 0, 1, 2});
  // [frame][joint] in centimetres.
  const double expected[4][4][3] = {
      // Rest pose.
      {{0, 0, 0}, {10, 0, 0}, {10, 20, 0}, {10, 20, 5}},
      // Root moved to x=100 and turned Rz(90): A = (100,10,0), B = A + Rz(0,20,0) = (80,10,0).
      {{100, 0, 0}, {100, 10, 0}, {80, 10, 0}, {80, 10, 5}},
      // A: Z=90 then X=90 (R = Rz Rx). B = A + Rz Rx (0,20,0) = (10,0,20);
      // End = B + Rz Rx (0,0,5) = B + Rz (0,-5,0) = (15,0,20). (Rx Rz would give B = (-10,0,0).)
      {{0, 0, 0}, {10, 0, 0}, {10, 0, 20}, {15, 0, 20}},
      // Root Yposition 50 replaces OFFSET y; B: X=90, End = B + Rx (0,0,5) = B + (0,-5,0).
      {{0, 50, 0}, {10, 50, 0}, {10, 70, 0}, {10, 65, 0}},
  };
  for (int t = 0; t < 4; ++t) {
    for (int j = 0; j < 4; ++j) {
      for (int a = 0; a < 3; ++a) {
        INFO("frame " << t << " joint " << j << " axis " << a);
        CHECK(std::abs(m.at(t, j)[a] - expected[t][j][a] * 0.01) < 1e-5);
      }
    }
  }

  // Without End Sites the same joints, minus B_End; scale applies.
  BvhOptions mm;
  mm.scale_to_metres = 0.001;
  const Motion m2 = ReadBvhText(kHandBvh, "hand.bvh", mm);
  REQUIRE(m2.num_joints() == 3);
  CHECK(std::abs(m2.at(2, 2)[2] - 0.020f) < 1e-6);
}

TEST_CASE("bvh: random hierarchies and channel orders match an independent FK", "[io][bvh]") {
  const std::vector<std::string> all = {"Xposition", "Yposition", "Zposition",
                                        "Xrotation", "Yrotation", "Zrotation"};
  std::mt19937 rng(1234);
  for (int trial = 0; trial < 40; ++trial) {
    Spec s;
    const int n = 1 + static_cast<int>(rng() % 12);
    std::uniform_real_distribution<double> off(-30, 30);
    for (int j = 0; j < n; ++j) {
      // Parent: any earlier joint whose subtree is still open keeps the order depth-first, so
      // attach to the previous joint or one of its ancestors.
      int parent = -1;
      if (j > 0) {
        parent = j - 1;
        while (s.joints[parent].parent >= 0 && rng() % 3 == 0) parent = s.joints[parent].parent;
        while (s.joints[parent].end_site) parent = s.joints[parent].parent;
      }
      SpecJoint jt{"J" + std::to_string(j), parent, {off(rng), off(rng), off(rng)}, {}, false};
      if (j > 0 && rng() % 5 == 0) {
        jt.end_site = true;
        jt.name = "";
      } else {
        std::vector<std::string> ch = all;
        std::shuffle(ch.begin(), ch.end(), rng);
        ch.resize(rng() % 7);
        jt.channels = ch;
      }
      s.joints.push_back(jt);
    }
    // A depth-first writer puts children right after their parent's block; reorder the spec to
    // file order so channel values line up.
    Spec ordered;
    std::vector<int> new_index(s.joints.size(), -1);
    std::function<void(int)> visit = [&](int j) {
      new_index[j] = static_cast<int>(ordered.joints.size());
      SpecJoint jt = s.joints[j];
      jt.parent = jt.parent < 0 ? -1 : new_index[jt.parent];
      ordered.joints.push_back(jt);
      for (int k = 0; k < n; ++k) {
        if (s.joints[k].parent == j) visit(k);
      }
    };
    visit(0);
    for (size_t j = 0; j < ordered.joints.size(); ++j) {
      if (ordered.joints[j].end_site) {
        ordered.joints[j].name = ordered.joints[ordered.joints[j].parent].name + "_End";
      }
    }
    if (TotalChannels(ordered) == 0) ordered.joints[0].channels = {"Yrotation"};
    AddRandomFrames(&ordered, 5, trial, 50, 180);
    // End Sites of one parent would share a name; keep only the first.
    std::map<std::string, int> end_count;
    bool duplicate_end = false;
    for (const auto& j : ordered.joints) {
      if (j.end_site && end_count[j.name]++) duplicate_end = true;
    }
    const std::string text = WriteBvh(ordered);
    INFO("trial " << trial << "\n" << text);
    for (bool ends : {false, true}) {
      BvhOptions opt;
      opt.include_end_sites = ends;
      if (ends && duplicate_end) {
        CHECK_THROWS_AS(ReadBvhText(text, "random.bvh", opt), FormatError);
        continue;
      }
      const Motion m = ReadBvhText(text, "random.bvh", opt);
      CheckAgainstReference(m, ordered, ends, 0.01);
    }
  }
}

TEST_CASE("bvh: CMU-style file (ZYX on joints, 120 fps, End Sites)", "[io][bvh]") {
  Spec s = MakeHumanoidSpec([](int j) -> std::vector<std::string> {
    if (j == 0) {
      return {"Xposition", "Yposition", "Zposition", "Zrotation", "Yrotation", "Xrotation"};
    }
    return {"Zrotation", "Yrotation", "Xrotation"};
  });
  s.frame_time = "0.008333";
  AddRandomFrames(&s, 30, 5, 100, 120);
  testing::TempDir dir;
  const std::string path = dir.file("cmu_style.bvh");
  {
    std::ofstream out(path, std::ios::binary);
    out << WriteBvh(s);
  }
  const Motion m = ReadBvhFile(path);
  CHECK(m.fps() == 120.0);
  CHECK(m.num_joints() == 10);
  CheckAgainstReference(m, s, false, 0.01);

  BvhOptions opt;
  opt.include_end_sites = true;
  const Motion e = ReadBvhFile(path, opt);
  REQUIRE(e.num_joints() == 13);
  CHECK(e.skeleton().Find("Head_End").has_value());
  CHECK(e.skeleton().Find("LowerArm_L_End").has_value());
  CHECK(e.skeleton().Find("Foot_R_End").has_value());
  CHECK(e.skeleton().parent(*e.skeleton().Find("Foot_R_End")) == *e.skeleton().Find("Foot_R"));
  CheckAgainstReference(e, s, true, 0.01);

  // Reading the same file with a different (wrong) order would not match: the order matters.
  Spec swapped = s;
  for (auto& j : swapped.joints) std::reverse(j.channels.begin(), j.channels.end());
  double max_diff = 0;
  for (size_t t = 0; t < s.frames.size(); ++t) {
    std::vector<double> rev;
    // Per joint, the values in reversed channel order, so only the composition order differs.
    size_t v = 0;
    for (const auto& j : s.joints) {
      std::vector<double> part(s.frames[t].begin() + v,
                               s.frames[t].begin() + v + j.channels.size());
      std::reverse(part.begin(), part.end());
      rev.insert(rev.end(), part.begin(), part.end());
      v += j.channels.size();
    }
    const auto a = ReferenceFk(s, s.frames[t], false);
    const auto b = ReferenceFk(swapped, rev, false);
    for (size_t j = 0; j < a.size(); ++j) max_diff = std::max(max_diff, (a[j] - b[j]).norm());
  }
  CHECK(max_diff > 1.0);  // cm: the fixture really exercises the rotation order
}

TEST_CASE("bvh: Bandai-style 6 channels per joint, position channels replace OFFSET", "[io][bvh]") {
  Spec s = MakeHumanoidSpec([](int) -> std::vector<std::string> {
    return {"Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation"};
  });
  AddRandomFrames(&s, 20, 9, 40, 90);
  const std::string text = WriteBvh(s);
  const Motion m = ReadBvhText(text, "bandai_style.bvh");
  CHECK(m.fps() == 30.0);
  CheckAgainstReference(m, s, false, 0.01);

  // With zero rotations, each joint sits at the sum of the position channels along its chain;
  // the OFFSETs (which differ) play no part.
  Spec still = s;
  still.frames.clear();
  std::vector<double> f;
  for (size_t j = 0; j < still.joints.size(); ++j) {
    if (still.joints[j].end_site) continue;
    f.insert(f.end(), {1.0 + j, 2.0 * j, -3.0, 0, 0, 0});
  }
  still.frames.push_back(f);
  const Motion z = ReadBvhText(WriteBvh(still), "still.bvh");
  const int head = z.skeleton().Index("Head");  // Hips(0) Spine(1) Chest(2) Neck(3) Head(4)
  double sum[3] = {0, 0, 0};
  for (int j : {0, 1, 2, 3, 4}) {
    sum[0] += 1.0 + j;
    sum[1] += 2.0 * j;
    sum[2] += -3.0;
  }
  for (int a = 0; a < 3; ++a) CHECK(std::abs(z.at(0, head)[a] - sum[a] * 0.01) < 1e-6);
}

TEST_CASE("bvh: CRLF, tabs and odd spacing give identical results", "[io][bvh]") {
  Spec s = MakeHumanoidSpec([](int j) -> std::vector<std::string> {
    if (j == 0)
      return {"Xposition", "Yposition", "Zposition", "Yrotation", "Xrotation", "Zrotation"};
    return {"Zrotation", "Xrotation", "Yrotation"};
  });
  AddRandomFrames(&s, 10, 3, 50, 170);
  const std::string lf = WriteBvh(s);
  BvhOptions opt;
  opt.include_end_sites = true;
  const Motion a = ReadBvhText(lf, "lf.bvh", opt);
  const Motion b = ReadBvhText(ToCrlf(lf), "crlf.bvh", opt);
  CHECK(a.positions() == b.positions());
  CHECK(a.skeleton().joint_names() == b.skeleton().joint_names());
  CHECK(a.fps() == b.fps());

  // Tabs, runs of spaces, blank lines, trailing whitespace, a UTF-8 BOM, lone CR line ends.
  std::string odd = "\xEF\xBB\xBF";
  for (char c : lf) {
    if (c == ' ') {
      odd += " \t  ";
    } else if (c == '\n') {
      odd += " \t\n";
    } else {
      odd += c;
    }
  }
  odd += "\n\n   \n";
  const Motion c = ReadBvhText(odd, "odd.bvh", opt);
  CHECK(a.positions() == c.positions());
  std::string cr = lf;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  const Motion d = ReadBvhText(cr, "cr.bvh", opt);
  CHECK(a.positions() == d.positions());
}

TEST_CASE("bvh: frame rate snapping", "[io][bvh]") {
  auto fps_of = [](const std::string& frame_time) {
    std::string text = kHandBvh;
    const size_t at = text.find("0.04");
    text.replace(at, 4, frame_time);
    return ReadBvhText(text, "fps.bvh").fps();
  };
  CHECK(fps_of("0.0333333") == 30.0);
  CHECK(fps_of("0.033333") == 30.0);
  CHECK(fps_of("0.008333") == 120.0);
  CHECK(fps_of("0.00833333") == 120.0);
  CHECK(fps_of("0.016667") == 60.0);
  CHECK(fps_of("0.0416667") == 24.0);
  CHECK(fps_of("0.01") == 100.0);
  CHECK(fps_of("8.333e-3") == 120.0);
  // Not a rounding of 1/n: kept as is.
  CHECK(std::abs(fps_of("0.03") - 1 / 0.03) < 1e-9);
  CHECK(std::abs(fps_of("0.0335") - 1 / 0.0335) < 1e-9);
}

// ---------------------------------------------------------------------------------------------
// Errors: each case names the file, the line (header) or frame (data), and what was wrong.

// kHandBvh as lines (1-based line numbers: line n is lines[n - 1]).
std::vector<std::string> HandLines() {
  std::vector<std::string> lines;
  std::istringstream in(kHandBvh);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::string Join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

std::string Replace(int line, const std::string& with) {
  auto lines = HandLines();
  lines.at(line - 1) = with;
  return Join(lines);
}

std::string Erase(int line) {
  auto lines = HandLines();
  lines.erase(lines.begin() + (line - 1));
  return Join(lines);
}

std::string ErrorOf(const std::string& text, const std::string& name, BvhOptions opt = {}) {
  try {
    ReadBvhText(text, name, opt);
  } catch (const FormatError& e) {
    return e.what();
  }
  return "<no error>";
}

struct ErrorCase {
  const char* name;
  std::string text;
  std::vector<std::string> expect;  // substrings of the message besides the file name
};

TEST_CASE("bvh: malformed files raise FormatError with file, place and cause", "[io][bvh]") {
  // Line numbers of kHandBvh: 1 HIERARCHY, 2 ROOT, 3 {, 4 OFFSET, 5 CHANNELS, 6 JOINT A, 7 {,
  // 8 OFFSET, 9 CHANNELS, 10 JOINT B, 11 {, 12 OFFSET, 13 CHANNELS, 14 End Site, 15 {,
  // 16 OFFSET, 17-20 }, 21 MOTION, 22 Frames, 23 Frame Time, 24-27 frames 0-3.
  const auto lines = HandLines();
  REQUIRE(lines.size() == 27);
  REQUIRE(lines[20] == "MOTION");
  std::string deep = "HIERARCHY\nROOT J0\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n";
  for (int j = 1; j < 1100; ++j) deep += "JOINT J" + std::to_string(j) + "\n{\nOFFSET 0 1 0\n";
  std::string many_frames = kHandBvh;
  many_frames.replace(many_frames.find("Frames: 4"), 9, "Frames: 6");
  std::string fewer_frames = kHandBvh;
  fewer_frames.replace(fewer_frames.find("Frames: 4"), 9, "Frames: 3");
  std::string cut_line = kHandBvh;
  cut_line.resize(cut_line.size() - 10);  // frame 3 keeps 8 numbers ("0 50 0 0 0 0 0 0")

  const std::vector<ErrorCase> cases = {
      {"empty", "", {"line 1", "empty"}},
      {"blank", "  \r\n\t\n", {"empty"}},
      {"no_hierarchy", Erase(1), {"line 1", "expected 'HIERARCHY'", "'ROOT'"}},
      {"no_root", Replace(2, "JOINT Root"), {"line 2", "ROOT"}},
      {"no_motion",
       Join(std::vector<std::string>(lines.begin(), lines.begin() + 20)),
       {"line 21", "expected 'MOTION'", "end of the file"}},
      {"motion_misspelt", Replace(21, "MOTON"), {"line 21", "MOTION", "'MOTON'"}},
      {"missing_close_brace",
       Erase(17),
       {"line 20", "unbalanced braces", "joint 'Root' (opened at line 2)", "'MOTION'"}},
      {"extra_close_brace", Replace(20, "}\n}"), {"line 21", "unbalanced braces"}},
      {"missing_open_brace", Erase(7), {"line 7", "expected '{'", "'OFFSET'"}},
      {"unknown_channel",
       Replace(9, "CHANNELS 3 Zrotation Xrot Yrotation"),
       {"line 9", "unknown channel name 'Xrot'"}},
      {"too_few_channel_names",
       Replace(9, "CHANNELS 3 Zrotation Xrotation"),
       {"line 10", "declares 3 channels", "lists only 2"}},
      {"too_many_channel_names",
       Replace(9, "CHANNELS 2 Zrotation Xrotation Yrotation"),
       {"line 9", "declares 2 channels", "'Yrotation'"}},
      {"channel_count_not_a_number",
       Replace(9, "CHANNELS three Zrotation"),
       {"line 9", "number of channels", "'three'"}},
      {"channel_count_seven", Replace(9, "CHANNELS 7 Zrotation"), {"line 9", "0..6", "'7'"}},
      {"channel_twice",
       Replace(9, "CHANNELS 3 Zrotation Zrotation Yrotation"),
       {"line 9", "listed twice"}},
      {"bad_offset", Replace(8, "OFFSET 10 zero 0"), {"line 8", "OFFSET", "'zero'"}},
      {"nan_offset", Replace(8, "OFFSET 10 nan 0"), {"line 8", "finite", "'nan'"}},
      {"missing_offset", Erase(8), {"line 9", "expected 'OFFSET x y z' in joint 'A'"}},
      {"unknown_keyword", Replace(8, "OFFSETS 10 0 0"), {"line 8", "'OFFSETS'"}},
      {"end_without_site", Replace(14, "End Sight"), {"line 14", "'Site'", "'Sight'"}},
      {"duplicate_joint",
       Replace(10, "JOINT A"),
       {"line 10", "duplicate joint name 'A'", "line 6"}},
      {"too_many_joints", deep, {"too many joints", "1024"}},
      {"frames_not_a_number", Replace(22, "Frames: four"), {"line 22", "frame count", "'four'"}},
      {"frames_negative", Replace(22, "Frames: -4"), {"line 22", "frame count", "'-4'"}},
      {"frames_fraction", Replace(22, "Frames: 4.5"), {"line 22", "'4.5'"}},
      {"frames_huge", Replace(22, "Frames: 9223372036854775807"), {"line 22", "above the limit"}},
      {"frames_overflow", Replace(22, "Frames: 99999999999999999999"), {"line 22", "frame count"}},
      {"frames_missing", Erase(22), {"line 22", "Frames:", "'Frame'"}},
      {"frame_time_zero", Replace(23, "Frame Time: 0"), {"line 23", "> 0", "'0'"}},
      {"frame_time_negative", Replace(23, "Frame Time: -0.04"), {"line 23", "> 0", "'-0.04'"}},
      {"frame_time_nan", Replace(23, "Frame Time: nan"), {"line 23", "'nan'"}},
      {"frame_time_missing", Erase(23), {"line 23", "Frame Time"}},
      {"truncated_frames", many_frames, {"frame 4", "ends after 4 frames", "expected 6"}},
      {"truncated_line",
       cut_line,
       {"frame 3 (line 27)", "expected 12 numbers, found 8", "truncated"}},
      {"too_few_values",
       Replace(25, "100 0 0 90 0 0 0 0 0 0 0"),
       {"frame 1 (line 25)", "expected 12 numbers, found 11"}},
      {"too_many_values",
       Replace(25, "100 0 0 90 0 0 0 0 0 0 0 0 7 8"),
       {"frame 1 (line 25)", "too many values", "found 14"}},
      {"not_a_number",
       Replace(26, "0 0 0 0 0 0 90 abc 0 0 0 0"),
       {"frame 2 (line 26)", "'abc'", "'A' Xrotation", "value 8 of 12"}},
      {"number_with_junk", Replace(26, "0 0 0 0 0 0 90 9O 0 0 0 0"), {"frame 2", "'9O'"}},
      {"nan_value", Replace(24, "0 0 0 NaN 0 0 0 0 0 0 0 0"), {"frame 0 (line 24)", "'NaN'"}},
      {"inf_value", Replace(27, "0 50 0 0 0 0 0 0 0 inf 0 0"), {"frame 3 (line 27)", "'inf'"}},
      {"huge_value",
       Replace(27, "0 1e999 0 0 0 0 0 0 0 0 0 0"),
       {"frame 3", "'1e999'", "out of range"}},
      {"overflowing_position",
       Replace(27, "0 1e300 0 0 0 0 0 0 0 0 0 0"),
       {"frame 3", "non-finite position"}},
      {"extra_frames", fewer_frames, {"line 27", "more data after the 3 frames"}},
      {"second_root", Replace(20, "}\nROOT X\n{\nOFFSET 0 0 0\n}"), {"line 21", "second ROOT"}},
      {"end_site_channels",
       Replace(16, "OFFSET 0 0 5\nCHANNELS 1 Xrotation"),
       {"line 17", "End Site cannot have CHANNELS"}},
      {"binary_junk", std::string("HIERARCHY\nROOT \x01\xff\n{"), {"line 2", "\\x01\\xff"}},
  };
  for (const auto& c : cases) {
    const std::string name = std::string(c.name) + ".bvh";
    const std::string msg = ErrorOf(c.text, name);
    INFO("case " << c.name << ": " << msg);
    CHECK(msg.rfind(name + ":", 0) == 0);
    for (const auto& e : c.expect) CHECK(msg.find(e) != std::string::npos);
  }

  // End Site names may clash with real joints only when End Sites are kept.
  const std::string clash = Replace(10, "JOINT A_End");
  const std::string renamed = Replace(6, "JOINT B_End");
  CHECK_NOTHROW(ReadBvhText(renamed, "clash.bvh"));
  BvhOptions ends;
  ends.include_end_sites = true;
  CHECK(ErrorOf(renamed, "clash.bvh", ends).find("duplicate joint name 'B_End'") !=
        std::string::npos);

  // The file name is the path given to ReadBvhFile; a missing file is a FormatError too.
  testing::TempDir dir;
  const std::string path = dir.file("broken.bvh");
  {
    std::ofstream out(path, std::ios::binary);
    out << Replace(25, "1 2 3");
  }
  try {
    ReadBvhFile(path);
    FAIL("expected a FormatError");
  } catch (const FormatError& e) {
    const std::string msg = e.what();
    CHECK(msg.find(path + ":frame 1 (line 25)") != std::string::npos);
  }
  CHECK_THROWS_AS(ReadBvhFile(dir.file("missing.bvh")), FormatError);
}

TEST_CASE("bvh: zero frames and zero-channel joints", "[io][bvh]") {
  std::string none = kHandBvh;
  none.resize(none.find("Frames: 4"));
  none += "Frames: 0\nFrame Time: 0.04\n";
  const Motion m = ReadBvhText(none, "none.bvh");
  CHECK(m.num_frames() == 0);
  CHECK(m.num_joints() == 3);

  const std::string fixed =
      "HIERARCHY\nROOT R\n{\n OFFSET 1 2 3\n CHANNELS 0\n JOINT C\n {\n  OFFSET 0 10 0\n"
      "  CHANNELS 1 Xrotation\n }\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n0\n90\n";
  const Motion f = ReadBvhText(fixed, "fixed.bvh");
  REQUIRE(f.num_frames() == 2);
  CHECK(f.fps() == 10.0);
  CHECK(std::abs(f.at(1, 0)[0] - 0.01f) < 1e-6);
  CHECK(std::abs(f.at(1, 1)[1] - 0.12f) < 1e-6);

  // No channels at all: every frame is the rest pose.
  const std::string rest =
      "HIERARCHY\nROOT R\n{\n OFFSET 1 2 3\n CHANNELS 0\n}\nMOTION\nFrames: 3\nFrame Time: 0.1\n";
  const Motion r = ReadBvhText(rest, "rest.bvh");
  REQUIRE(r.num_frames() == 3);
  CHECK(std::abs(r.at(2, 0)[2] - 0.03f) < 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Real data: every clip of both Bandai archives.

TEST_CASE("bvh: every Bandai clip reads (real data)", "[io][bvh][data]") {
  const std::string dir = testing::SharedDataDir("data/bandai");
  if (dir.empty()) {
    std::printf("SKIPPED: ../shared/data/bandai not found\n");
    return;
  }
  const std::vector<std::string> names = {
      "joint_Root", "Hips",       "Spine",      "Chest",      "Neck",       "Head",
      "Shoulder_L", "UpperArm_L", "LowerArm_L", "Hand_L",     "Shoulder_R", "UpperArm_R",
      "LowerArm_R", "Hand_R",     "UpperLeg_L", "LowerLeg_L", "Foot_L",     "Toes_L",
      "UpperLeg_R", "LowerLeg_R", "Foot_R",     "Toes_R"};
  const auto is_bvh = [](const std::string& p) {
    return p.size() > 4 && p.compare(p.size() - 4, 4, ".bvh") == 0;
  };
  struct Expect {
    const char* archive;
    int clips;
    long frames_min, frames_max;
  };
  // Frame totals from the data README (dataset-2: "about 340,000").
  for (const Expect& ex : {Expect{"bandai-1.tar.xz", 174, 31914, 31914},
                           Expect{"bandai-2.tar.xz", 2549, 320000, 360000}}) {
    const auto start = std::chrono::steady_clock::now();
    int clips = 0, implausible = 0;
    long frames = 0;
    size_t bytes = 0;
    double parse_seconds = 0;
    std::vector<std::string> odd;
    ForEachArchiveFile(
        dir + "/" + ex.archive, is_bvh, [&](const std::string& entry, std::string_view text) {
          const auto t0 = std::chrono::steady_clock::now();
          Motion m;
          try {
            m = ReadBvhText(text, entry);
          } catch (const FormatError& e) {
            FAIL(e.what());
          }
          parse_seconds +=
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          bytes += text.size();
          ++clips;
          frames += m.num_frames();
          INFO(entry);
          REQUIRE(m.skeleton().joint_names() == names);
          REQUIRE(m.fps() == 30.0);
          REQUIRE(m.num_frames() > 0);
          const auto& p = m.positions();
          REQUIRE(std::all_of(p.begin(), p.end(), [](float v) { return std::isfinite(v); }));
          const Skeleton& s = m.skeleton();
          const float head = m.at(0, s.Index("Head"))[1];
          const float foot = std::min(m.at(0, s.Index("Foot_L"))[1], m.at(0, s.Index("Foot_R"))[1]);
          const float height = head - foot;
          if (!(height > 1.0f && height < 2.2f)) {
            ++implausible;
            if (odd.size() < 10) {
              odd.push_back(entry + " head-foot " + std::to_string(height) + " m");
            }
          }
        });
    const double total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "%s: %d clips, %ld frames, %.1f MB BVH, parse %.2f s (%.0f MB/s), total %.1f s, "
        "%d clips with head-foot height outside 1.0-2.2 m in frame 0\n",
        ex.archive, clips, frames, bytes / 1e6, parse_seconds,
        bytes / 1e6 / std::max(parse_seconds, 1e-9), total, implausible);
    for (const auto& o : odd) std::printf("  %s\n", o.c_str());
    CHECK(clips == ex.clips);
    CHECK(frames >= ex.frames_min);
    CHECK(frames <= ex.frames_max);
    CHECK(implausible <= clips / 20);  // "most clips": at least 95 %
  }
}

}  // namespace
}  // namespace motionfork
