// Whether a campaign can still write its outputs after one write failed. A full or read-only
// output device fails every later recording too, after its analysis: the campaign stops feeding
// recordings instead, and names the ones it did not start, so that an overnight run does not
// spend hours on results it cannot keep. A rerun, once there is room, analyses them.
#pragma once

#include <string>

namespace fogpipe::graph {

/// Why nothing more can be written into `output_dir`, after a write there failed with
/// `error_text` (an exception's what(), which for HDF5 holds the system's error message);
/// "" when the failure concerns one file only (a per-file size limit, a damaged result).
/// Decided from the error (ENOSPC, EDQUOT, EROFS) and from statvfs(3) of the folder.
std::string OutputExhaustedReason(const std::string& output_dir, const std::string& error_text);

/// The same after a write(2) or fsync(2) that failed with `error_number`.
std::string OutputExhaustedReason(const std::string& output_dir, int error_number);

}  // namespace fogpipe::graph
