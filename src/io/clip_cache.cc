#include "io/clip_cache.h"

#include <cstring>
#include <filesystem>
#include <memory>
#include <new>

#include "core/error.h"
#include "io/file_util.h"

namespace motionfork {
namespace {

constexpr char kMagic[8] = {'M', 'F', 'C', 'L', 'I', 'P', 'S', '\0'};
constexpr uint32_t kVersion = 1;

class Writer {
 public:
  template <typename T>
  void Put(T v) {
    const size_t n = out_.size();
    out_.resize(n + sizeof(T));
    std::memcpy(out_.data() + n, &v, sizeof(T));
  }
  void PutString(const std::string& s) {
    Put<uint32_t>(static_cast<uint32_t>(s.size()));
    out_.append(s);
  }
  void PutFloats(const std::vector<float>& v) {
    out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(const std::string& bytes, const std::string& path) : b_(bytes), path_(path) {}
  template <typename T>
  T Get() {
    Need(sizeof(T), "a number");
    T v;
    std::memcpy(&v, b_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string GetString() {
    const uint32_t n = Get<uint32_t>();
    Need(n, "a string");
    std::string s = b_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  std::vector<float> GetFloats(size_t n) {
    Need(n * sizeof(float), "position data");
    std::vector<float> v(n);
    std::memcpy(v.data(), b_.data() + pos_, n * sizeof(float));
    pos_ += n * sizeof(float);
    return v;
  }
  bool AtEnd() const { return pos_ == b_.size(); }
  // A count of items of at least min_bytes each, checked against the bytes left before anything
  // is allocated for them.
  uint32_t GetCount(size_t min_bytes, const char* what) {
    const uint32_t n = Get<uint32_t>();
    if (static_cast<uint64_t>(n) * min_bytes > b_.size() - pos_) {
      throw FormatError(FormatMessage(path_, "byte " + std::to_string(pos_),
                                      "corrupt cache: " + std::to_string(n) + " " + what +
                                          " cannot fit in the " + std::to_string(b_.size() - pos_) +
                                          " bytes left"));
    }
    return n;
  }
  // Throws when fewer than n bytes are left.
  void Need(size_t n, const char* what) {
    if (n > b_.size() - pos_) {
      throw FormatError(FormatMessage(path_, "byte " + std::to_string(pos_),
                                      std::string("cache is truncated: expected ") + what + " of " +
                                          std::to_string(n) + " bytes, found " +
                                          std::to_string(b_.size() - pos_) +
                                          " (delete the file to rebuild it)"));
    }
  }

 private:
  const std::string& b_;
  const std::string& path_;
  size_t pos_ = 0;
};

}  // namespace

uint64_t Fnv1a64(const std::string& text, uint64_t seed) {
  uint64_t h = seed;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

void WriteClipCache(const std::string& path, uint64_t key, const std::vector<CachedClip>& clips) {
  std::vector<const Skeleton*> skeletons;
  std::vector<uint32_t> skeleton_of(clips.size());
  for (size_t c = 0; c < clips.size(); ++c) {
    const Skeleton& s = clips[c].motion.skeleton();
    size_t k = 0;
    while (k < skeletons.size() && !skeletons[k]->SameStructure(s)) ++k;
    if (k == skeletons.size()) skeletons.push_back(&s);
    skeleton_of[c] = static_cast<uint32_t>(k);
  }
  Writer w;
  w.bytes().append(kMagic, sizeof(kMagic));
  w.Put<uint32_t>(kVersion);
  w.Put<uint64_t>(key);
  w.Put<uint32_t>(static_cast<uint32_t>(skeletons.size()));
  for (const Skeleton* s : skeletons) {
    w.PutString(s->name());
    w.Put<uint32_t>(static_cast<uint32_t>(s->num_joints()));
    for (int j = 0; j < s->num_joints(); ++j) {
      w.PutString(s->joint_name(j));
      w.Put<int32_t>(s->parent(j));
    }
  }
  w.Put<uint32_t>(static_cast<uint32_t>(clips.size()));
  for (size_t c = 0; c < clips.size(); ++c) {
    const CachedClip& clip = clips[c];
    w.PutString(clip.name);
    w.PutString(clip.group);
    w.PutString(clip.subject);
    w.PutString(clip.action);
    w.Put<uint32_t>(skeleton_of[c]);
    w.Put<double>(clip.motion.fps());
    w.Put<uint32_t>(static_cast<uint32_t>(clip.motion.num_frames()));
    w.PutFloats(clip.motion.positions());
  }
  WriteFileAtomically(path, w.bytes());
}

bool ReadClipCache(const std::string& path, uint64_t key, std::vector<CachedClip>* clips) {
  clips->clear();
  if (!std::filesystem::is_regular_file(path)) return false;
  const std::string bytes = ReadFileBytes(path);
  if (bytes.size() < sizeof(kMagic) + 12 ||
      std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    throw FormatError(
        FormatMessage(path, "", "not a motionfork clip cache (bad magic); delete it"));
  }
  Reader r(bytes, path);
  for (size_t i = 0; i < sizeof(kMagic); ++i) r.Get<char>();
  if (r.Get<uint32_t>() != kVersion) return false;
  if (r.Get<uint64_t>() != key) return false;
  // A skeleton is at least a name and a joint count, a clip four names and three numbers.
  std::vector<std::shared_ptr<const Skeleton>> skeletons(r.GetCount(8, "skeletons"));
  try {
    for (auto& s : skeletons) {
      std::string name = r.GetString();
      const uint32_t J = r.Get<uint32_t>();
      if (J == 0 || J > 100000) throw std::invalid_argument("bad joint count " + std::to_string(J));
      r.Need(static_cast<size_t>(J) * 8, "joint names and parents");
      std::vector<std::string> names(J);
      std::vector<int> parents(J);
      for (uint32_t j = 0; j < J; ++j) {
        names[j] = r.GetString();
        parents[j] = r.Get<int32_t>();
      }
      s = std::make_shared<const Skeleton>(Skeleton::FromParents(name, names, parents));
    }
    const uint32_t n = r.GetCount(32, "clips");
    clips->reserve(n);
    for (uint32_t c = 0; c < n; ++c) {
      CachedClip clip;
      clip.name = r.GetString();
      clip.group = r.GetString();
      clip.subject = r.GetString();
      clip.action = r.GetString();
      const uint32_t k = r.Get<uint32_t>();
      if (k >= skeletons.size()) throw std::invalid_argument("bad skeleton index");
      const double fps = r.Get<double>();
      const uint32_t frames = r.Get<uint32_t>();
      std::vector<float> p =
          r.GetFloats(static_cast<size_t>(frames) * skeletons[k]->num_joints() * 3);
      clip.motion = Motion(skeletons[k], fps, std::move(p));
      clips->push_back(std::move(clip));
    }
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(
        path, "", std::string("corrupt cache (") + e.what() + "); delete the file to rebuild it"));
  } catch (const std::bad_alloc&) {
    throw FormatError(FormatMessage(path, "", "corrupt cache (out of memory reading it)"));
  }
  if (!r.AtEnd()) throw FormatError(FormatMessage(path, "", "corrupt cache: trailing bytes"));
  return true;
}

}  // namespace motionfork
