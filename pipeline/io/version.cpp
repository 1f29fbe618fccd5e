#include "pipeline/io/version.h"

#include "fogpipe_git_commit.h"

namespace fogpipe {
const char* Version() { return FOGPIPE_VERSION; }
const char* GitCommit() { return FOGPIPE_GIT_COMMIT; }
}  // namespace fogpipe
