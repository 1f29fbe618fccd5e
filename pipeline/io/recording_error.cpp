#include "pipeline/io/recording_error.h"

#include <utility>

namespace fogpipe::io {

RecordingError::RecordingError(std::string kind, std::string file, std::string problem)
    : std::runtime_error(file + ": " + problem),
      kind_(std::move(kind)),
      file_(std::move(file)),
      problem_(std::move(problem)) {}

}  // namespace fogpipe::io
