// Reading files straight out of archives (.tar.xz, .tar.gz, .zip, ... via libarchive), so a
// dataset shipped as archives is used without unpacking it anywhere.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace motionfork {

// Calls visit(entry_path, bytes) for every regular file in the archive for which want(entry_path)
// is true, in archive order. Throws FormatError naming the archive (and entry) on a read error.
// progress, when given, is called after each visited file with the share of the (compressed)
// archive consumed so far, in [0, 1].
void ForEachArchiveFile(const std::string& archive_path,
                        const std::function<bool(const std::string&)>& want,
                        const std::function<void(const std::string&, std::string_view)>& visit,
                        const std::function<void(double)>& progress = nullptr);

// True for names that look like archives libarchive reads (.tar, .tar.xz, .txz, .tar.gz, .tgz,
// .tar.bz2, .zip).
bool LooksLikeArchive(const std::string& path);

}  // namespace motionfork
