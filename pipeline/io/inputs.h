// The campaign's input list: what `fogpipe run INPUT... [--manifest FILE]` processes.
//
// The list is built once, sorted and de-duplicated, before anything is read, so that every process
// of a sharded campaign (`--shard I --num-shards N`, see SelectShard in campaign_manifest.h) sees
// the same list and the same output names.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fogpipe::io {

struct InputFile {
  /// Path as given (files, manifest entries) or as found (folders, globs), made lexically normal.
  std::string path;
  /// Size in bytes from the file system; from the manifest's second column if it has one and the
  /// file cannot be stat'ed (then the reader reports the file as missing).
  std::uintmax_t size_bytes = 0;
  /// File name of the results file inside OUTDIR, e.g. "run1.fogpipe.h5" (see AssignOutputNames).
  std::string output_name;
};

/// Expands the command-line inputs:
///  - a file is taken as is (any extension);
///  - a folder contributes every regular file named *.h5 below it (recursively);
///  - anything else is a glob(3) pattern (quote it so the shell leaves it alone);
///  - `manifest` (may be empty): one path per line (ParseManifestLine); blank lines and comments
///    are skipped; an optional second column holds the size in bytes (ignored except as a
///    fallback). Relative paths are relative to the manifest's folder.
/// Problems (a pattern or folder matching nothing, an unreadable manifest, a missing file) are
/// appended to *errors, one message each naming the input; the rest is still listed. Missing files
/// named explicitly are kept in the list so that they are reported per file (status "failed").
/// The result is sorted by path without duplicates, and has output names assigned.
std::vector<InputFile> ListInputs(const std::vector<std::string>& arguments,
                                  const std::string& manifest, std::vector<std::string>* errors);

/// Why `path`, a file an option names (--config, --manifest, --model), cannot be read as one:
/// "there is no such file", "it is a folder", "it is a FIFO, device or socket" (opening one can
/// block for ever); "" for a regular file (also through a symlink).
std::string RegularFileProblem(const std::string& path);

/// A path as a manifest spells it: as is when it holds no whitespace, '#', '"' or '\'; otherwise
/// in double quotes, with '"' and '\' preceded by '\', and line feeds and carriage returns written
/// as \n and \r.
std::string QuoteManifestPath(const std::string& path);

/// One manifest line: `PATH [SIZE] [# comment]`. PATH is quoted as QuoteManifestPath writes it
/// or a run of non-blank characters; '#' starts a comment only where a field would start (so
/// "run#3.h5" is a path).
struct ManifestLine {
  bool empty = true;  ///< blank or comment only
  std::string path;
  std::string size;   ///< "" when absent
  std::string error;  ///< not empty when the line cannot be read
};
ManifestLine ParseManifestLine(const std::string& line);

/// Names the results file of each input "<stem>.fogpipe.h5". When several inputs share a stem
/// (a/x.h5 and b/x.h5), every one of them becomes "<stem>-<first 8 hex of SHA-256 of its path>
/// .fogpipe.h5", which depends only on that input's path, so it is stable across reruns and shards.
void AssignOutputNames(std::vector<InputFile>* inputs);

}  // namespace fogpipe::io
