#pragma once

namespace fogpipe {
/// Semantic version of this build, e.g. "0.1.0".
const char* Version();
/// Git commit the build was configured from, or "unknown".
const char* GitCommit();
}  // namespace fogpipe
