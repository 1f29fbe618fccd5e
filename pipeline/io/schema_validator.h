// Layout schemas (schemas/*.json, format "fogpipe-schema-v1", documented in schemas/README.md)
// and the engine that checks an HDF5 file against one.
//
// A schema describes groups, datasets and attributes: their type class (float, integer, number,
// string), rank, required or optional, allowed values (`enum`, numeric bounds, a regex), allowed
// `units`, repeated objects whose names follow a pattern ("imf_<k:int>", "<axis>") with counts,
// whether unknown objects are ignored or forbidden, and the file-wide rule that every numeric
// dataset has a `units` attribute. Validation reports every problem found, not only the first.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "pipeline/hdf5/file.h"

namespace fogpipe::io {

/// A schema file that cannot be used (bad JSON, unknown key, bad pattern). A usage error, not a
/// property of the file being validated.
class SchemaError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SchemaProblem {
  std::string object;   ///< path inside the file, e.g. "/rate" or "/" for the root
  std::string message;  ///< what is wrong, for people
};

struct ValidationReport {
  std::string file;
  std::string schema;  ///< the schema's name, e.g. "recording-v1"
  std::vector<SchemaProblem> problems;
  long long objects_checked = 0;  ///< groups + datasets + attributes examined
  bool valid() const { return problems.empty(); }
};

class Schema {
 public:
  /// Parses a schema; `origin` names it in error messages. Throws SchemaError.
  static Schema FromJsonText(const std::string& text, const std::string& origin);
  /// Reads and parses a schema file. Throws SchemaError.
  static Schema FromFile(const std::string& path);

  Schema(Schema&&) noexcept;
  Schema& operator=(Schema&&) noexcept;
  ~Schema();

  const std::string& name() const;
  const std::string& title() const;

  /// Checks an open file. The caller holds LockHdf5(). HDF5 failures while walking the file
  /// become problems ("cannot read ..."), never exceptions.
  ValidationReport Validate(const hdf5::File& file) const;

  struct Impl;

 private:
  explicit Schema(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// Where schema files are looked for, in order: `explicit_dir` (the --schemas option) if not
/// empty, $FOGPIPE_SCHEMAS_DIR, the installed schemas relative to the running executable
/// (<prefix>/bin/fogpipe -> <prefix>/share/fogpipe/schemas, GNUInstallDirs), and, for a binary
/// inside the build tree only, the source tree's schemas/ folder (compile-time paths).
std::vector<std::string> SchemaSearchPath(const std::string& explicit_dir);

/// The path of "<name>.json" in the first folder of the search path that has it; empty if none.
std::string FindSchemaFile(const std::string& name, const std::string& explicit_dir);

}  // namespace fogpipe::io
