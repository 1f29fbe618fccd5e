#include "pipeline/io/isolated_reader.h"

#include <cstring>
#include <new>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <type_traits>

#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/recording_check.h"

namespace fogpipe::io {
namespace {

// The child's exit codes.
constexpr int kOk = 0;
constexpr int kRecordingProblem = 1;  ///< output: kind '\n' problem
constexpr int kOtherError = 2;        ///< output: what()
constexpr int kOutOfMemory = 3;

/// Runs `body` (which may throw RecordingError) in a child and turns every way it can end
/// badly into a RecordingError naming `path` and `what` the child was doing.
void RunReaderChild(const std::string& path, const std::string& what,
                    const std::function<void(std::string*)>& body, const IsolationLimits& limits,
                    std::string* output) {
  auto child = [&](std::string* out) {
    try {
      body(out);
      return kOk;
    } catch (const RecordingError& e) {
      *out = e.kind() + "\n" + e.problem();
      return kRecordingProblem;
    } catch (const std::bad_alloc&) {
      out->clear();
      return kOutOfMemory;
    } catch (const std::exception& e) {
      *out = e.what();
      return kOtherError;
    }
  };
  IsolatedOutcome outcome;
  {
    auto lock = hdf5::LockHdf5();  // inherited by the child; see isolated_call.h
    outcome = RunIsolated(child, limits);
  }
  using End = IsolatedOutcome::End;
  if (outcome.end == End::kExited && outcome.exit_code == kOk) {
    *output = std::move(outcome.output);
    return;
  }
  if (outcome.end == End::kExited && outcome.exit_code == kRecordingProblem) {
    const std::size_t newline = outcome.output.find('\n');
    throw RecordingError(outcome.output.substr(0, newline), path,
                         newline == std::string::npos ? "" : outcome.output.substr(newline + 1));
  }
  if (outcome.end == End::kExited && outcome.exit_code == kOtherError) {
    throw RecordingError(error_kind::kCorruptFile, path, what + ": " + outcome.output);
  }
  if (outcome.end == End::kExited && outcome.exit_code == kOutOfMemory) {
    throw RecordingError(error_kind::kReaderOutOfMemory, path,
                         what + " needed more than the " +
                             std::to_string(limits.extra_memory_bytes >> 20) +
                             " MiB allowed (a damaged or implausible file); not analysed");
  }
  if (outcome.Interrupted()) {
    throw RecordingError(error_kind::kInterrupted, path, what + " interrupted by a stop request");
  }
  if (outcome.end == End::kSignalled) {
    throw RecordingError(error_kind::kReaderCrashed, path,
                         "the HDF5 library " + outcome.Describe(limits) + " while " + what +
                             " (damaged HDF5 metadata); the crash was contained in a child "
                             "process, the file is not analysed");
  }
  if (outcome.end == End::kTimedOut) {
    throw RecordingError(error_kind::kReaderTimeout, path,
                         what + " " + outcome.Describe(limits) +
                             " (damaged metadata that loops, or a file that blocks); stopped");
  }
  throw RecordingError(error_kind::kUnreadableFile, path, what + " " + outcome.Describe(limits));
}

std::string ToWire(const RecordingInfo& info) {
  nlohmann::json j;
  j["path"] = info.path;
  j["samples"] = info.samples;
  j["axis_count"] = info.axis_count;
  j["two_dimensional"] = info.two_dimensional;
  j["axis_names"] = info.axis_names;
  j["axis_names_from_file"] = info.axis_names_from_file;
  j["rate_units"] = info.rate_units;
  j["rate_dtype"] = info.rate_dtype;
  j["rate_scale_factor"] = info.rate_scale_factor;
  j["rate_chunk"] = info.rate_chunk;
  j["sample_rate_hz"] = info.sample_rate_hz;
  if (info.start_time_utc) j["start_time_utc"] = *info.start_time_utc;
  if (info.instrument) j["instrument"] = *info.instrument;
  if (info.serial) j["serial"] = *info.serial;
  if (info.latitude_deg) j["latitude_deg"] = *info.latitude_deg;
  for (const AuxChannelInfo& a : info.aux)
    j["aux"].push_back({a.name, a.units, a.dtype, a.scale_factor});
  j["file_size_bytes"] = info.file_size_bytes;
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

RecordingInfo FromWire(const std::string& wire) {
  const nlohmann::json j = nlohmann::json::parse(wire);
  RecordingInfo info;
  info.path = j.at("path").get<std::string>();
  info.samples = j.at("samples").get<long long>();
  info.axis_count = j.at("axis_count").get<int>();
  info.two_dimensional = j.at("two_dimensional").get<bool>();
  info.axis_names = j.at("axis_names").get<std::vector<std::string>>();
  info.axis_names_from_file = j.at("axis_names_from_file").get<bool>();
  info.rate_units = j.at("rate_units").get<std::string>();
  const auto unit = units::ParseRateUnit(info.rate_units);
  if (!unit) throw std::runtime_error("unknown units '" + info.rate_units + "'");
  info.rate_unit = *unit;
  info.rate_dtype = j.at("rate_dtype").get<std::string>();
  info.rate_scale_factor = j.at("rate_scale_factor").get<double>();
  info.rate_chunk = j.at("rate_chunk").get<std::vector<unsigned long long>>();
  info.sample_rate_hz = j.at("sample_rate_hz").get<double>();
  if (j.contains("start_time_utc")) info.start_time_utc = j["start_time_utc"].get<std::string>();
  if (j.contains("instrument")) info.instrument = j["instrument"].get<std::string>();
  if (j.contains("serial")) info.serial = j["serial"].get<std::string>();
  if (j.contains("latitude_deg")) info.latitude_deg = j["latitude_deg"].get<double>();
  if (j.contains("aux")) {
    for (const auto& a : j["aux"]) info.aux.push_back({a[0], a[1], a[2], a[3].get<double>()});
  }
  info.file_size_bytes = j.at("file_size_bytes").get<long long>();
  return info;
}

}  // namespace

IsolationLimits DataReadLimits() {
  IsolationLimits limits;
  limits.seconds = 600.0;
  return limits;
}

RecordingInfo InspectRecordingIsolated(const std::string& path, const IsolationLimits& limits) {
  // The child's findings come back as JSON: the parent never opens the file itself (HDF5 can
  // corrupt memory on damaged metadata without crashing at once, so repeating the inspection
  // here would not be safe even after the child succeeded).
  std::string wire;
  RunReaderChild(
      path, "reading its metadata", [&](std::string* out) { *out = ToWire(AdmitRecording(path)); },
      limits, &wire);
  try {
    return FromWire(wire);
  } catch (const std::exception& e) {
    throw RecordingError(error_kind::kUnreadableFile, path,
                         std::string("the inspection's report could not be read: ") + e.what());
  }
}

namespace {

/// One column read by `read` in a child; the samples come back through the pipe.
Eigen::VectorXd ReadColumnIsolated(
    const RecordingInfo& info, const std::string& what,
    const std::function<Eigen::VectorXd(const RecordingReader&, ReadReport*)>& read,
    ReadReport* report, const IsolationLimits& limits) {
  const std::string& path = info.path;
  static_assert(std::is_trivially_copyable<ReadReport>::value,
                "the report crosses the pipe as bytes (the child is this same binary)");
  std::string output;
  IsolationLimits read_limits = limits;
  auto body = [&](std::string* out) {
    RecordingReader reader(path);
    ReadReport local;
    const Eigen::VectorXd x = read(reader, &local);
    out->assign(reinterpret_cast<const char*>(&local), sizeof(local));
    out->append(reinterpret_cast<const char*>(x.data()),
                static_cast<std::size_t>(x.size()) * sizeof(double));
  };
  // The column itself is allowed on top of the limit, twice (the vector and the pipe's copy).
  read_limits.extra_memory_bytes += 2 * static_cast<std::uint64_t>(info.samples) * sizeof(double);
  RunReaderChild(path, what, body, read_limits, &output);
  if (output.size() < sizeof(ReadReport) ||
      (output.size() - sizeof(ReadReport)) % sizeof(double) != 0) {
    throw RecordingError(
        error_kind::kUnreadableFile, path,
        what + ": the reader process returned " + std::to_string(output.size()) + " bytes");
  }
  ReadReport local;
  std::memcpy(&local, output.data(), sizeof(local));
  const auto n = static_cast<Eigen::Index>((output.size() - sizeof(ReadReport)) / sizeof(double));
  Eigen::VectorXd x(n);
  std::memcpy(x.data(), output.data() + sizeof(ReadReport), static_cast<std::size_t>(n) * 8);
  if (report) *report = local;
  return x;
}

}  // namespace

Eigen::VectorXd ReadAxisRadPerSecondIsolated(const RecordingInfo& info, const std::string& axis,
                                             const ReadOptions& options, ReadReport* report,
                                             const IsolationLimits& limits) {
  return ReadColumnIsolated(
      info, "reading /rate axis '" + axis + "'",
      [&](const RecordingReader& reader, ReadReport* local) {
        return reader.ReadAxisRadPerSecond(axis, options, local);
      },
      report, limits);
}

Eigen::VectorXd ReadAuxIsolated(const RecordingInfo& info, const std::string& name,
                                const ReadOptions& options, ReadReport* report,
                                const IsolationLimits& limits) {
  return ReadColumnIsolated(
      info, "reading /aux/" + name,
      [&](const RecordingReader& reader, ReadReport* local) {
        return reader.ReadAux(name, options, local);
      },
      report, limits);
}

}  // namespace fogpipe::io
