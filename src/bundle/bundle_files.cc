#include "bundle/bundle_files.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "core/error.h"
#include "io/file_util.h"

namespace motionfork {

namespace fs = std::filesystem;

std::string BundleChecksum(std::string_view bytes) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[32];
  std::snprintf(buf, sizeof(buf), "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return buf;
}

namespace {

[[noreturn]] void Fail(const std::string& file, const std::string& what) {
  throw FormatError(FormatMessage(file, "", what));
}

void Rename(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  if (ec) Fail(to.string(), "cannot move " + from.string() + " into place: " + ec.message());
}

}  // namespace

void WriteBundle(const std::string& dir, const std::vector<BundleFile>& files,
                 const std::string& manifest_name,
                 const std::function<std::string(const BundleChecksums&)>& manifest) {
  const fs::path target = fs::absolute(fs::path(dir)).lexically_normal();
  const fs::path base = target.has_filename() ? target : target.parent_path();
  std::vector<NamedBytes> set;
  BundleChecksums sums;
  for (const BundleFile& f : files) {
    set.push_back({f.name, f.bytes});
    sums[f.name] = BundleChecksum(f.bytes);
  }
  set.push_back({manifest_name, manifest(sums)});
  if (fs::exists(base)) {  // replace the bundle's files as one set; the folder's others stay
    WriteFileSet(base.string(), set);
    return;
  }
  // A new bundle: the whole folder written aside, then renamed into place.
  const fs::path temp =
      base.parent_path() / ("." + base.filename().string() + ".tmp-" + std::to_string(getpid()));
  std::error_code ec;
  fs::remove_all(temp, ec);
  fs::create_directories(temp, ec);
  if (ec) Fail(temp.string(), "cannot create the bundle's temporary folder: " + ec.message());
  try {
    for (const NamedBytes& f : set) WriteFileAtomically((temp / f.name).string(), f.bytes);
    fs::create_directories(base.parent_path(), ec);
    Rename(temp, base);
  } catch (...) {
    fs::remove_all(temp, ec);
    throw;
  }
}

void RequireBundleFiles(const std::string& dir, const std::string& kind,
                        const std::vector<std::string>& names) {
  if (!fs::is_directory(dir)) Fail(dir, kind + " bundle folder not found");
  std::string expected;
  for (size_t i = 0; i < names.size(); ++i)
    expected += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  for (const std::string& n : names) {
    const fs::path f = fs::path(dir) / n;
    if (!fs::is_regular_file(f))
      Fail(f.string(), "missing from the " + kind + " bundle (expected " + expected + ")");
  }
}

void RequireChecksum(const std::string& dir, const std::string& name,
                     const BundleChecksums& checksums, const std::string& manifest_name) {
  if (checksums.count(name)) return;
  Fail((fs::path(dir) / manifest_name).string(),
       "records no checksum of " + name +
           " (a bundle written before motionfork verified bundles); rewrite it with "
           "'motionfork bundle upgrade " +
           dir + "'");
}

std::string ReadBundleFile(const std::string& dir, const std::string& name,
                           const BundleChecksums& checksums, const std::string& manifest_name) {
  const std::string path = (fs::path(dir) / name).string();
  std::string bytes = ReadFileBytes(path);
  const auto it = checksums.find(name);
  if (it != checksums.end()) {
    const std::string found = BundleChecksum(bytes);
    if (found != it->second) {
      Fail(path, "checksum " + found + " does not match " + manifest_name + "'s " + it->second +
                     " (the weights belong to another bundle or are damaged)");
    }
  }
  return bytes;
}

}  // namespace motionfork
