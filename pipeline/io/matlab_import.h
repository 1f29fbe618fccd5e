// MATLAB v7.3 MAT-files (and other HDF5 files holding a rate matrix) read for `fogpipe import`
// (recording_import.h writes them as contract-v1 recordings).
//
// A v7.3 MAT-file is an HDF5 file behind a 512-byte user block (MATLAB's text header). Each
// variable is a dataset of the root group with a string attribute MATLAB_class ("double",
// "single", "int16", ...); a struct is a group with MATLAB_class "struct" holding its fields.
// MATLAB stores arrays column-major, and HDF5 lists dimensions row-major, so the HDF5 dims are
// the MATLAB dims reversed: an N x 3 matrix has HDF5 dims [3, N].
//
// The shape rule:
// - A dataset WITH a MATLAB_class attribute has MATLAB dims = the HDF5 dims reversed. One
//   without it (written by h5py, numpy or C) is taken as its dims say, [N] or [N, A].
// - The matrix is then read as N x A: one row per sample, one column per axis (MATLAB's own
//   convention for time series). A vector, 1 x N or N x 1, is one axis whatever its orientation.
// - A matrix with more columns than rows is refused ("a transposed matrix?"): a recording has
//   more samples than axes, so such a matrix holds one sample per column and must be transposed
//   (rate.') before it is saved.
//
// Older MAT-files (v4, and v5/v7, MATLAB's default) are not HDF5; they are refused with advice
// (save with -v7.3, or export CSV).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "pipeline/io/recording_import.h"

namespace fogpipe::io {

/// What a file is, by its first bytes.
enum class ImportSourceKind {
  kText,        ///< anything else: read as text
  kHdf5,        ///< the HDF5 signature at 0 or at a user-block size (512, 1024, ...): v7.3
  kOldMatFile,  ///< "MATLAB 5.0 MAT-file" header (v5, v7) or a .mat name without HDF5 (v4)
};

/// The kind of the file at `path`; nullopt with *error (naming the file) when it cannot be read.
std::optional<ImportSourceKind> DetectImportSourceKind(const std::string& path, std::string* error);

/// The refusal of an older MAT-file: what to do instead.
std::string OldMatFileMessage(const std::string& path);

struct MatlabImportOptions {
  /// The rate matrix: a variable ("rate"), a struct field ("gyro.rate") or an HDF5 path
  /// ("/gyro/rate"). Required (no default): without it the import fails, listing the variables.
  std::string variable;
  /// A scalar variable holding the sample rate in Hz. "" (default): metadata.sample_rate_hz,
  /// which is then required; giving both is an error.
  std::string sample_rate_variable;
  /// Units, scale factor (integer classes are counts), sample rate, axis names, aux channels
  /// (their sources are variables: vectors of N values), root attributes.
  ImportMetadataOptions metadata;

  bool IsValid(std::string* error) const;
  /// The MATLAB-specific options (metadata apart), for the provenance.
  nlohmann::json ToJson() const;
};

/// Reads the rate matrix (and aux vectors) from the HDF5 file at `path`, opened read-only, and
/// applies the options (FinishImport). Never throws for problems of the file. Takes the HDF5
/// lock itself: do not call it while holding hdf5::LockHdf5().
ImportResult ImportMatlab(const std::string& path, const MatlabImportOptions& options);

/// The metadata checks of ImportMatlab alone (variables found, their classes, shapes and
/// storage), without reading a sample: what a short-lived child process runs first, so that
/// damaged metadata that loops is stopped in seconds. "" when they pass, else why not.
std::string CheckMatlabVariables(const std::string& path, const MatlabImportOptions& options);

}  // namespace fogpipe::io
