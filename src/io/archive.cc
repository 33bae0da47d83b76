#include "io/archive.h"

#include <archive.h>
#include <archive_entry.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/error.h"
#include "io/file_util.h"

namespace motionfork {

namespace {
bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

bool LooksLikeArchive(const std::string& path) {
  for (const char* ext : {".tar", ".tar.xz", ".txz", ".tar.gz", ".tgz", ".tar.bz2", ".zip"}) {
    if (EndsWith(path, ext)) return true;
  }
  return false;
}

void ForEachArchiveFile(const std::string& archive_path,
                        const std::function<bool(const std::string&)>& want,
                        const std::function<void(const std::string&, std::string_view)>& visit,
                        const std::function<void(double)>& progress) {
  // Regular files only: libarchive would wait forever on a FIFO.
  if (const std::string problem = InputFileProblem(archive_path); !problem.empty()) {
    throw FormatError(FormatMessage(archive_path, "", problem));
  }
  std::error_code ec;
  const double total_bytes = static_cast<double>(std::filesystem::file_size(archive_path, ec));
  std::unique_ptr<struct archive, decltype(&archive_read_free)> a(archive_read_new(),
                                                                  &archive_read_free);
  archive_read_support_filter_all(a.get());
  archive_read_support_format_all(a.get());
  if (archive_read_open_filename(a.get(), archive_path.c_str(), 1 << 20) != ARCHIVE_OK) {
    throw FormatError(FormatMessage(
        archive_path, "", std::string("cannot open archive: ") + archive_error_string(a.get())));
  }
  struct archive_entry* entry = nullptr;
  std::vector<char> buffer;
  for (;;) {
    const int r = archive_read_next_header(a.get(), &entry);
    if (r == ARCHIVE_EOF) break;
    if (r != ARCHIVE_OK && r != ARCHIVE_WARN) {
      throw FormatError(FormatMessage(
          archive_path, "", std::string("corrupt archive: ") + archive_error_string(a.get())));
    }
    if (archive_entry_filetype(entry) != AE_IFREG) continue;
    const std::string name = archive_entry_pathname(entry);
    if (!want(name)) continue;
    const la_int64_t size = archive_entry_size(entry);
    buffer.resize(size > 0 ? static_cast<size_t>(size) : 0);
    size_t got = 0;
    while (got < buffer.size()) {
      const la_ssize_t n = archive_read_data(a.get(), buffer.data() + got, buffer.size() - got);
      if (n < 0) {
        throw FormatError(
            FormatMessage(archive_path, name,
                          std::string("cannot read entry: ") + archive_error_string(a.get())));
      }
      if (n == 0) break;
      got += static_cast<size_t>(n);
    }
    if (got != buffer.size()) {
      throw FormatError(FormatMessage(archive_path, name,
                                      "entry is truncated: expected " +
                                          std::to_string(buffer.size()) + " bytes, found " +
                                          std::to_string(got)));
    }
    visit(name, std::string_view(buffer.data(), buffer.size()));
    if (progress && total_bytes > 0) {
      progress(std::min(1.0, static_cast<double>(archive_filter_bytes(a.get(), -1)) / total_bytes));
    }
  }
}

}  // namespace motionfork
