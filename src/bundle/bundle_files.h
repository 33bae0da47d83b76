// The one bundle reader/writer. A bundle is a folder holding a manifest (YAML, written by the
// bundle layer: bundle/*_bundle.h) and weight files whose checksums the manifest records:
//
//   checksums:
//     hgvae.pt: fnv1a64:0123456789abcdef
//
// (FNV-1a 64, the checksum the pose prior's bundles have always carried as weights_checksum.)
// Bundles written before checksums existed record none: the LibTorch bundles refuse them
// (RequireChecksum; `motionfork bundle upgrade` rewrites them), the others load them unchecked.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace motionfork {

struct BundleFile {
  std::string name;   // file name inside the bundle folder ("hgvae.pt")
  std::string bytes;  // its whole content
};

// File name -> checksum ("fnv1a64:" and 16 hex digits).
using BundleChecksums = std::map<std::string, std::string>;

std::string BundleChecksum(std::string_view bytes);

// Writes `files` and the manifest `manifest_name`, whose text `manifest` makes from the files'
// checksums, into dir, all-or-nothing: a new bundle is written in a temporary sibling folder and
// renamed into place; an existing one has its files replaced as one set (io/file_util.h
// WriteFileSet: the other files of dir - checkpoint/, prior/, constraints.yaml - stay, a failed or
// killed write is rolled back). Throws FormatError naming what failed.
void WriteBundle(const std::string& dir, const std::vector<BundleFile>& files,
                 const std::string& manifest_name,
                 const std::function<std::string(const BundleChecksums&)>& manifest);

// Checks that dir is a folder holding `names`; FormatError "<kind> bundle folder not found" or
// "<file>: missing from the <kind> bundle (expected a and b)".
void RequireBundleFiles(const std::string& dir, const std::string& kind,
                        const std::vector<std::string>& names);

// Checks that the manifest `manifest_name` of dir records a checksum of `name`: FormatError naming
// the manifest and saying how to rewrite a bundle written before checksums existed.
void RequireChecksum(const std::string& dir, const std::string& name,
                     const BundleChecksums& checksums, const std::string& manifest_name);

// Reads dir/name and, when `checksums` records it, checks its checksum: a mismatch is a FormatError
// naming the file, both checksums and the manifest.
std::string ReadBundleFile(const std::string& dir, const std::string& name,
                           const BundleChecksums& checksums, const std::string& manifest_name);

}  // namespace motionfork
