// Whole-file reading (regular files only, bounded size) and all-or-nothing writing of one file or
// of a set of files.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace motionfork {

// The largest file ReadFileBytes reads: 2 GiB, or MOTIONFORK_MAX_INPUT_MB megabytes (MiB) when
// that environment variable holds a positive integer.
uint64_t MaxInputFileBytes();

// Why `path` cannot be read as an input file, or "" when it can: it does not exist, is a dangling
// symbolic link or a symbolic link loop, a folder, a FIFO (named pipe), a socket or a device.
// Never blocks (a FIFO is not opened).
std::string InputFileProblem(const std::string& path);

// Called with the first bytes of a file (up to 4096) before the rest is read; throws to refuse the
// file (e.g. a wrong magic number) without reading gigabytes first.
using FileHeadCheck = std::function<void(std::string_view head)>;

// A FileHeadCheck for text formats: refuses a head holding a NUL byte ("PATH:byte N: expected
// <what>, found binary data (a NUL byte)"), e.g. a sparse or binary file given as a CSV.
FileHeadCheck RequireTextHead(const std::string& path, const std::string& what);

// Reads a whole regular file into memory. Throws FormatError naming the file when it cannot be
// opened, is not a regular file (InputFileProblem), is larger than MaxInputFileBytes() (the
// message says how to raise the limit), or when memory runs out.
std::string ReadFileBytes(const std::string& path, const FileHeadCheck& check_head = nullptr);

// Writes bytes to path through a temporary file in the same folder (PATH.tmp<pid>), fsync and a
// rename (the folder synced too), so a reader never sees a half-written file and a failed write
// leaves no file behind. Leftover temporary files of killed writers to the same path are removed
// first. Throws FormatError naming the file and the system's reason.
void WriteFileAtomically(const std::string& path, std::string_view bytes);

struct NamedBytes {
  std::string name;   // file name inside the folder
  std::string bytes;  // its whole content
};

// Replaces the files `files` (names inside dir; other files of dir stay) all-or-nothing as a set:
// they are written and synced in a temporary sibling folder (dir/.<first name>.tmp<pid>), the
// existing files of those names moved aside, the new ones moved in, and the old ones restored when
// a step fails. A write killed half-way is rolled back by the next WriteFileSet or
// RecoverFileSets on dir, so readers that call RecoverFileSets first never see old and new files
// mixed. Throws FormatError naming what failed.
void WriteFileSet(const std::string& dir, const std::vector<NamedBytes>& files);

// Rolls back the file-set writes (WriteFileSet) in dir that were killed before they completed and
// removes their temporary folders; writes of live processes are left alone.
void RecoverFileSets(const std::string& dir);

// Checks an output path before anything is computed: it must name a file (not "" and not a
// folder-only name such as "dir/" or "..") and no input (the same file after resolving symbolic
// links and "..", or a hard link to it). A prediction's output OUT writes OUT.npy and OUT.json, and
// an input that is a prediction is read with the other file of its pair, so both of each pair are
// compared. Throws std::invalid_argument naming the output and the input it would overwrite.
void RequireSeparateOutput(const std::string& output, const std::vector<std::string>& inputs);

// The same for a bundle written from another: out_dir must not be in_dir (after resolving links
// and ".."). Throws std::invalid_argument "<what>: --out OUT is the input bundle; ...".
void RequireSeparateFolder(const std::string& what, const std::string& out_dir,
                           const std::string& in_dir);

}  // namespace motionfork
