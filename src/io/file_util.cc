#include "io/file_util.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>
#include <stdexcept>

#include "core/error.h"
#include "core/text_format.h"

namespace motionfork {

namespace fs = std::filesystem;

namespace {

constexpr uint64_t kDefaultMaxInputBytes = uint64_t{2} << 30;  // 2 GiB
constexpr size_t kHeadBytes = 4096;

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw FormatError(FormatMessage(path, "", what));
}

std::string ErrnoText(int err) { return std::strerror(err); }

// "3.00 GiB" style sizes for messages.
std::string ReadableBytes(uint64_t bytes) {
  if (bytes >= (uint64_t{1} << 30)) return StringPrintf("%.2f GiB", bytes / double(1 << 30));
  if (bytes >= (uint64_t{1} << 20)) return StringPrintf("%.2f MiB", bytes / double(1 << 20));
  return std::to_string(bytes) + " bytes";
}

// What a file of this type is, for "expected a regular file" messages.
std::string NotRegularProblem(mode_t mode) {
  const char* kind = S_ISDIR(mode)    ? "a folder"
                     : S_ISFIFO(mode) ? "a FIFO (named pipe), which may never end"
                     : S_ISSOCK(mode) ? "a socket"
                     : S_ISCHR(mode)  ? "a character device"
                     : S_ISBLK(mode)  ? "a block device"
                                      : "not a regular file";
  return std::string("is ") + kind + "; expected a regular file";
}

std::string OpenProblem(const std::string& path, int err) {
  if (err == ELOOP) return "symbolic link loop (too many levels of symbolic links)";
  if (err == ENOENT) {
    struct stat st;
    if (::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
      return "is a symbolic link to a file that does not exist";
    }
    return "file does not exist";
  }
  return "cannot open: " + ErrnoText(err);
}

class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }
  // Closes now; returns 0 or the errno of close().
  int Close() {
    const int r = ::close(fd_);
    fd_ = -1;
    return r == 0 ? 0 : errno;
  }

 private:
  int fd_;
};

// Reads exactly n bytes at dst; returns the count read (less at the end of the file).
size_t ReadUpTo(int fd, char* dst, size_t n, const std::string& path) {
  size_t got = 0;
  while (got < n) {
    const ssize_t r = ::read(fd, dst + got, n - got);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) Fail(path, "read failed: " + ErrnoText(errno));
    if (r == 0) break;
    got += static_cast<size_t>(r);
  }
  return got;
}

void WriteAll(int fd, std::string_view bytes, const std::string& path) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t r = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) Fail(path, "write failed: " + ErrnoText(errno));
    done += static_cast<size_t>(r);
  }
}

// Makes a completed rename or creation in `dir` durable; best effort (some file systems refuse).
void SyncFolder(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// Writes and fsyncs a new file (no rename).
void WriteSyncedFile(const fs::path& file, std::string_view bytes, const std::string& name) {
  Fd fd(::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666));
  if (fd.get() < 0) Fail(name, "cannot write: " + ErrnoText(errno));
  WriteAll(fd.get(), bytes, name);
  if (::fsync(fd.get()) != 0) Fail(name, "cannot sync the written data: " + ErrnoText(errno));
  if (const int err = fd.Close()) Fail(name, "write failed: " + ErrnoText(err));
}

void Rename(const fs::path& from, const fs::path& to, const std::string& name) {
  if (::rename(from.c_str(), to.c_str()) != 0) {
    const int err = errno;  // before anything else can change it
    Fail(name, "cannot move " + from.string() + " into place: " + ErrnoText(err));
  }
}

// The process id of a temporary name "<prefix><digits>" (0 when it is not one).
long TemporaryOwner(const std::string& name, const std::string& prefix) {
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return 0;
  const std::string digits = name.substr(prefix.size());
  if (digits.size() > 18 || !std::all_of(digits.begin(), digits.end(), ::isdigit)) return 0;
  return std::max(1L, std::atol(digits.c_str()));
}

bool ProcessIsAlive(long pid) {
  if (pid == static_cast<long>(::getpid())) return false;  // ours: a leftover of an earlier call
  if (pid > 4194304) return false;                         // above Linux's pid_max
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

// Calls f(entry) for the leftovers "<prefix><pid>" in dir whose writer is gone.
template <typename F>
void ForEachLeftover(const fs::path& dir, const std::string& prefix, F f) {
  std::error_code ec;
  std::vector<fs::path> found;
  for (fs::directory_iterator it(dir.empty() ? "." : dir, ec), end; !ec && it != end;
       it.increment(ec)) {
    const long owner = TemporaryOwner(it->path().filename().string(), prefix);
    if (owner > 0 && !ProcessIsAlive(owner)) found.push_back(it->path());
  }
  for (const fs::path& p : found) f(p);
}

// Removes the temporary files "<name>.tmp<pid>" of killed writers of dir/name.
void RemoveLeftoverFiles(const fs::path& dir, const std::string& name) {
  ForEachLeftover(dir, name + ".tmp", [](const fs::path& p) {
    std::error_code ec;
    if (fs::is_regular_file(fs::symlink_status(p, ec))) fs::remove(p, ec);
  });
}

std::string TemporarySuffix() { return ".tmp" + std::to_string(::getpid()); }

// File sets: dir/.<first>.tmp<pid>/ holds "names" (one per line), new/ (the new files) and, once
// the old files are being moved aside, old/.
std::vector<std::string> SetNames(const fs::path& temp) {
  std::vector<std::string> names;
  std::error_code ec;
  if (!fs::is_regular_file(temp / "names", ec)) return names;
  const std::string text = ReadFileBytes((temp / "names").string());
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = text.find('\n', begin);
    names.push_back(text.substr(begin, end - begin));
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return names;
}

// Puts the old files back (a set that did not complete) and removes the temporary folder.
void RollBack(const fs::path& dir, const fs::path& temp) {
  std::error_code ec;
  if (fs::is_directory(temp / "old", ec)) {
    for (const std::string& name : SetNames(temp)) {
      if (fs::exists(temp / "old" / name, ec)) {
        fs::rename(temp / "old" / name, dir / name, ec);
      } else if (!fs::exists(temp / "new" / name, ec)) {
        fs::remove(dir / name, ec);  // installed, and there was no file before
      }
    }
    SyncFolder(dir);
  }
  fs::remove_all(temp, ec);
}

void InstallSet(const fs::path& dir, const fs::path& temp, const std::vector<NamedBytes>& files) {
  for (const NamedBytes& f : files) {
    std::error_code ec;
    if (fs::is_directory(fs::symlink_status(dir / f.name, ec))) {
      Fail((dir / f.name).string(), "is a folder; expected a file to replace");
    }
  }
  fs::create_directory(temp / "old");
  for (const NamedBytes& f : files) {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(dir / f.name, ec))) {
      Rename(dir / f.name, temp / "old" / f.name, (dir / f.name).string());
    }
  }
  for (const NamedBytes& f : files) {
    Rename(temp / "new" / f.name, dir / f.name, (dir / f.name).string());
  }
  SyncFolder(dir);
}

fs::path Resolved(const fs::path& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec);
  return ec ? fs::absolute(p, ec).lexically_normal() : r;
}

bool SameFile(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec) && !ec;
  return Resolved(a) == Resolved(b);
}

// The files a path stands for: itself, and for a prediction (.npy, .json or no extension) both
// files of the pair.
std::vector<fs::path> PairFiles(const std::string& path, bool bare_names_too) {
  const fs::path p(path);
  const std::string ext = p.extension().string();
  std::vector<fs::path> out = {p};
  if (ext == ".npy" || ext == ".json" || (bare_names_too && ext.empty())) {
    const fs::path base = ext.empty() ? p : fs::path(p).replace_extension();
    out.push_back(base.string() + ".npy");
    out.push_back(base.string() + ".json");
  }
  return out;
}

}  // namespace

uint64_t MaxInputFileBytes() {
  const char* env = std::getenv("MOTIONFORK_MAX_INPUT_MB");
  if (env && *env) {
    char* end = nullptr;
    const unsigned long long mb = std::strtoull(env, &end, 10);
    if (end && *end == '\0' && mb > 0 && mb < (uint64_t{1} << 40)) return mb << 20;
  }
  return kDefaultMaxInputBytes;
}

std::string InputFileProblem(const std::string& path) {
  if (path.empty()) return "empty file name";
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) return OpenProblem(path, errno);
  if (!S_ISREG(st.st_mode)) return NotRegularProblem(st.st_mode);
  return "";
}

FileHeadCheck RequireTextHead(const std::string& path, const std::string& what) {
  return [path, what](std::string_view head) {
    const size_t nul = head.find('\0');
    if (nul != std::string_view::npos) {
      throw FormatError(FormatMessage(path, "byte " + std::to_string(nul),
                                      "expected " + what + ", found binary data (a NUL byte)"));
    }
  };
}

std::string ReadFileBytes(const std::string& path, const FileHeadCheck& check_head) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; the type is checked before any read.
  Fd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (fd.get() < 0) Fail(path, OpenProblem(path, errno));
  struct stat st;
  if (::fstat(fd.get(), &st) != 0) Fail(path, "cannot read: " + ErrnoText(errno));
  if (!S_ISREG(st.st_mode)) Fail(path, NotRegularProblem(st.st_mode));
  const uint64_t size = static_cast<uint64_t>(st.st_size), limit = MaxInputFileBytes();
  if (size > limit) {
    Fail(path, "the file is " + ReadableBytes(size) + ", above the " + ReadableBytes(limit) +
                   " limit on input files (set MOTIONFORK_MAX_INPUT_MB to raise it)");
  }
  std::string bytes;
  try {
    const size_t head = static_cast<size_t>(std::min<uint64_t>(size, kHeadBytes));
    bytes.resize(head);
    bytes.resize(ReadUpTo(fd.get(), bytes.data(), head, path));
    if (check_head) check_head(bytes);
    bytes.resize(static_cast<size_t>(size));
    const size_t rest = ReadUpTo(fd.get(), bytes.data() + head, bytes.size() - head, path);
    if (head + rest != size) Fail(path, "short read: the file shrank while it was read");
  } catch (const std::bad_alloc&) {
    Fail(path, "out of memory while reading the file (" + ReadableBytes(size) + ")");
  }
  return bytes;
}

void WriteFileAtomically(const std::string& path, std::string_view bytes) {
  const fs::path target(path);
  const fs::path dir = target.parent_path();
  if (!dir.empty()) {
    std::error_code ec;
    fs::create_directories(dir, ec);
  }
  RemoveLeftoverFiles(dir, target.filename().string());
  const fs::path tmp = target.string() + TemporarySuffix();
  try {
    WriteSyncedFile(tmp, bytes, path);
    Rename(tmp, target, path);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  SyncFolder(dir);
}

void RecoverFileSets(const std::string& dir) {
  std::error_code ec;
  const fs::path d(dir);
  if (!fs::is_directory(d, ec)) return;
  std::vector<fs::path> sets;
  for (fs::directory_iterator it(d, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const size_t at = name.rfind(".tmp");
    if (name.size() > 1 && name[0] == '.' && at != std::string::npos && it->is_directory(ec)) {
      sets.push_back(it->path());
    }
  }
  for (const fs::path& p : sets) {
    const std::string name = p.filename().string();
    ForEachLeftover(d, name.substr(0, name.rfind(".tmp") + 4),
                    [&](const fs::path& leftover) { RollBack(d, leftover); });
  }
}

void WriteFileSet(const std::string& dir, const std::vector<NamedBytes>& files) {
  if (files.empty()) return;
  const fs::path d = dir.empty() ? fs::path(".") : fs::path(dir);
  std::error_code ec;
  fs::create_directories(d, ec);
  RecoverFileSets(d.string());
  for (const NamedBytes& f : files) RemoveLeftoverFiles(d, f.name);
  const fs::path temp = d / ("." + files.front().name + TemporarySuffix());
  fs::remove_all(temp, ec);
  if (!fs::create_directories(temp / "new", ec) || ec) {
    Fail((d / files.front().name).string(),
         "cannot create a temporary folder in " + d.string() + ": " + ec.message());
  }
  try {
    std::string names;
    for (const NamedBytes& f : files) {
      WriteSyncedFile(temp / "new" / f.name, f.bytes, (d / f.name).string());
      names += f.name + "\n";
    }
    WriteSyncedFile(temp / "names", names, (d / files.front().name).string());
    SyncFolder(temp / "new");
    SyncFolder(temp);
    InstallSet(d, temp, files);
  } catch (...) {
    RollBack(d, temp);
    throw;
  }
  fs::remove(temp / "names", ec);  // the commit point: without it, nothing is rolled back
  fs::remove_all(temp, ec);
}

void RequireSeparateOutput(const std::string& output, const std::vector<std::string>& inputs) {
  if (output.empty()) {
    throw std::invalid_argument("the output path is empty; expected a file name");
  }
  const std::string file = fs::path(output).filename().string();
  if (output.back() == '/' || file == "." || file == "..") {
    throw std::invalid_argument("the output '" + output +
                                "' names a folder; expected a file name (e.g. " +
                                (fs::path(output) / "out").string() + ")");
  }
  for (const fs::path& o : PairFiles(output, true)) {
    for (const std::string& input : inputs) {
      if (input.empty()) continue;
      for (const fs::path& i : PairFiles(input, false)) {
        if (SameFile(o, i)) {
          const std::string named = i.string() == input ? "" : " (" + input + ")";
          throw std::invalid_argument("the output " + o.string() + " is the input " + i.string() +
                                      named +
                                      ": it would be overwritten; choose another output name");
        }
      }
    }
  }
}

void RequireSeparateFolder(const std::string& what, const std::string& out_dir,
                           const std::string& in_dir) {
  if (SameFile(out_dir, in_dir)) {
    throw std::invalid_argument(what + ": --out " + out_dir +
                                " is the input bundle; expected another folder");
  }
}

}  // namespace motionfork
