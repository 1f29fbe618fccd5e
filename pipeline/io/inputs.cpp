#include "pipeline/io/inputs.h"

#include <glob.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "pipeline/io/sha256.h"

namespace fogpipe::io {
namespace fs = std::filesystem;
namespace {

void AddFile(const fs::path& path, std::uintmax_t fallback_size, std::vector<InputFile>* out) {
  InputFile input;
  input.path = path.lexically_normal().string();
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  input.size_bytes = ec ? fallback_size : size;
  out->push_back(std::move(input));
}

void AddFolder(const fs::path& folder, std::vector<InputFile>* out,
               std::vector<std::string>* errors) {
  std::error_code ec;
  const std::size_t before = out->size();
  for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    // Every *.h5 entry but a folder: a FIFO or a device there is listed and then refused by
    // name at inspection (not_regular_file), never dropped without a word.
    std::error_code kind_ec;
    if (it->path().extension() == ".h5" && !it->is_directory(kind_ec)) {
      AddFile(it->path(), 0, out);
    }
  }
  if (ec) errors->push_back(folder.string() + ": cannot list folder: " + ec.message());
  if (out->size() == before) errors->push_back(folder.string() + ": folder holds no *.h5 file");
}

void AddGlob(const std::string& pattern, std::vector<InputFile>* out,
             std::vector<std::string>* errors) {
  glob_t matches{};
  const int rc = ::glob(pattern.c_str(), 0, nullptr, &matches);
  if (rc != 0) {
    errors->push_back(pattern + ": no such file, folder or matching pattern");
  } else {
    for (std::size_t i = 0; i < matches.gl_pathc; ++i) {
      const fs::path match(matches.gl_pathv[i]);
      if (fs::is_directory(match)) {
        AddFolder(match, out, errors);
      } else {
        AddFile(match, 0, out);
      }
    }
  }
  ::globfree(&matches);
}

// Reads one field at `*pos` (after blanks): a quoted path with '\' escapes, or a run of
// non-blank characters. False at the end of the line or at a comment; *error on a bad quote.
bool NextField(const std::string& line, std::size_t* pos, std::string* field, std::string* error) {
  std::size_t i = line.find_first_not_of(" \t\r", *pos);
  if (i == std::string::npos || line[i] == '#') return false;
  field->clear();
  if (line[i] == '"') {
    for (++i; i < line.size() && line[i] != '"'; ++i) {
      if (line[i] == '\\' && i + 1 < line.size()) {
        ++i;
        *field += line[i] == 'n' ? '\n' : line[i] == 'r' ? '\r' : line[i];
        continue;
      }
      *field += line[i];
    }
    if (i >= line.size()) {
      *error = "unterminated quote";
      return false;
    }
    *pos = i + 1;
    if (*pos < line.size() && line.find_first_of(" \t\r", *pos) != *pos) {
      *error = "text right after a closing quote";
      return false;
    }
    return true;
  }
  const std::size_t end = line.find_first_of(" \t\r", i);
  *field = line.substr(i, end == std::string::npos ? std::string::npos : end - i);
  *pos = end == std::string::npos ? line.size() : end;
  return true;
}

void AddManifest(const std::string& manifest, std::vector<InputFile>* out,
                 std::vector<std::string>* errors) {
  if (const std::string problem = RegularFileProblem(manifest); !problem.empty()) {
    errors->push_back(manifest + ": --manifest needs a manifest file, but " + problem);
    return;
  }
  std::ifstream in(manifest);
  if (!in) {
    errors->push_back(manifest + ": cannot read manifest");
    return;
  }
  const fs::path base = fs::path(manifest).parent_path();
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const ManifestLine parsed = ParseManifestLine(line);
    if (parsed.empty) continue;
    if (!parsed.error.empty()) {
      errors->push_back(manifest + ":" + std::to_string(line_number) + ": " + parsed.error);
      continue;
    }
    const std::string& path_text = parsed.path;
    std::uintmax_t size = 0;
    try {
      if (!parsed.size.empty()) size = std::stoull(parsed.size);
    } catch (const std::out_of_range&) {
      errors->push_back(manifest + ":" + std::to_string(line_number) + ": size out of range");
      continue;
    }
    fs::path path(path_text);
    if (path.is_relative()) path = base / path;
    AddFile(path, size, out);
  }
}

}  // namespace

std::string RegularFileProblem(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) return "there is no such file";
  if (fs::is_directory(status)) return "it is a folder";
  if (!fs::is_regular_file(status)) return "it is a FIFO, device or socket";
  return "";
}

std::string QuoteManifestPath(const std::string& path) {
  if (path.find_first_of(" \t\r\n#\"\\") == std::string::npos && !path.empty()) return path;
  // A line break in a name is written as \n (and \r), so that one path stays one line.
  std::string quoted = "\"";
  for (char c : path) {
    if (c == '\n') {
      quoted += "\\n";
    } else if (c == '\r') {
      quoted += "\\r";
    } else {
      if (c == '"' || c == '\\') quoted += '\\';
      quoted += c;
    }
  }
  return quoted + "\"";
}

ManifestLine ParseManifestLine(const std::string& line) {
  ManifestLine out;
  std::size_t pos = 0;
  std::string field, error;
  if (!NextField(line, &pos, &field, &error)) {
    out.empty = error.empty();
    out.error = error;
    return out;
  }
  out.empty = false;
  out.path = field;
  if (NextField(line, &pos, &field, &error)) {
    const bool digits =
        !field.empty() && field.find_first_not_of("0123456789") == std::string::npos;
    std::string extra;
    if (!digits) {
      error = "second column must be a size in bytes, got '" + field +
              "' (a path with spaces or '#' goes in double quotes)";
    } else if (NextField(line, &pos, &extra, &error)) {
      error = "expected 'PATH [SIZE]', got extra text '" + extra + "'";
    } else {
      out.size = field;
    }
  }
  out.error = error;
  return out;
}

std::vector<InputFile> ListInputs(const std::vector<std::string>& arguments,
                                  const std::string& manifest, std::vector<std::string>* errors) {
  std::vector<InputFile> inputs;
  for (const std::string& argument : arguments) {
    std::error_code ec;
    const fs::path path(argument);
    if (fs::is_directory(path, ec)) {
      AddFolder(path, &inputs, errors);
    } else if (fs::exists(path, ec)) {
      AddFile(path, 0, &inputs);
    } else if (argument.find_first_of("*?[") != std::string::npos) {
      AddGlob(argument, &inputs, errors);
    } else {
      // Kept so that the missing file is reported in status.jsonl like any other bad input.
      AddFile(path, 0, &inputs);
    }
  }
  if (!manifest.empty()) AddManifest(manifest, &inputs, errors);
  std::sort(inputs.begin(), inputs.end(),
            [](const InputFile& a, const InputFile& b) { return a.path < b.path; });
  inputs.erase(std::unique(inputs.begin(), inputs.end(),
                           [](const InputFile& a, const InputFile& b) { return a.path == b.path; }),
               inputs.end());
  AssignOutputNames(&inputs);
  return inputs;
}

void AssignOutputNames(std::vector<InputFile>* inputs) {
  std::map<std::string, int> stem_count;
  for (const InputFile& input : *inputs) ++stem_count[fs::path(input.path).stem().string()];
  for (InputFile& input : *inputs) {
    const std::string stem = fs::path(input.path).stem().string();
    input.output_name = stem_count[stem] > 1
                            ? stem + "-" + Sha256Hex(input.path).substr(0, 8) + ".fogpipe.h5"
                            : stem + ".fogpipe.h5";
  }
}

}  // namespace fogpipe::io
