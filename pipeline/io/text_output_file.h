// Text outputs (CSV tables, manifests, JSON sidecars, model histories) written as a whole or not
// at all, like the HDF5 outputs (pipeline/hdf5/atomic_output_file.h): a temporary file in the
// same folder, synced, then renamed over the final name. A killed process or a full disk never
// leaves a truncated file under the final name, and a rerun recognises the temporary's name.
#pragma once

#include <string>

namespace fogpipe::io {

/// Writes `text` to `path`. A symbolic link at `path` is refused, neither written through nor
/// replaced. Throws std::runtime_error naming the file and the system's reason.
void WriteTextFileAtomically(const std::string& path, const std::string& text);

}  // namespace fogpipe::io
