#include "pipeline/graph/output_space.h"

#include <sys/statvfs.h>

#include <cerrno>
#include <cstring>

namespace fogpipe::graph {
namespace {

/// Below this much free space no results file fits: the smallest one (a short single-axis
/// record without stored components) takes more.
constexpr unsigned long long kMinFreeBytes = 64ull << 10;

/// What statvfs says of the folder; "" when it has room or cannot be asked.
std::string FromStatvfs(const std::string& output_dir, bool write_failed_for_space) {
  struct statvfs fs {};
  if (::statvfs(output_dir.c_str(), &fs) != 0) return "";
  if ((fs.f_flag & ST_RDONLY) != 0) {
    return "the output folder " + output_dir + " is on a read-only filesystem";
  }
  const unsigned long long free_bytes =
      static_cast<unsigned long long>(fs.f_bavail) * static_cast<unsigned long long>(fs.f_frsize);
  if (write_failed_for_space || free_bytes < kMinFreeBytes) {
    return "the output device of " + output_dir + " is full (" + std::to_string(free_bytes >> 10) +
           " KiB free)";
  }
  return "";
}

}  // namespace

std::string OutputExhaustedReason(const std::string& output_dir, const std::string& error_text) {
  // The system's message for the errno, as HDF5 and std::filesystem quote it; a quota or a
  // read-only filesystem outranks a full device when a text names several.
  int error_number = error_text.find("errno = 28,") != std::string::npos ? ENOSPC : 0;
  for (int candidate : {ENOSPC, EROFS, EDQUOT}) {
    if (error_text.find(std::strerror(candidate)) != std::string::npos) error_number = candidate;
  }
  return OutputExhaustedReason(output_dir, error_number);
}

std::string OutputExhaustedReason(const std::string& output_dir, int error_number) {
  if (error_number == EDQUOT) return "the disk quota of " + output_dir + " is exhausted";
  if (error_number == EROFS) {
    return "the output folder " + output_dir + " is on a read-only filesystem";
  }
  return FromStatvfs(output_dir, error_number == ENOSPC);
}

}  // namespace fogpipe::graph
