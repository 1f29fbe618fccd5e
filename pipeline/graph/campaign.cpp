#include "pipeline/graph/campaign.h"

#include <fcntl.h>
#include <oneapi/tbb/flow_graph.h>
#include <oneapi/tbb/global_control.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "algorithms/method/preprocess.h"
#include "algorithms/method/tables.h"
#include "algorithms/model/compensate.h"
#include "pipeline/graph/interrupt.h"
#include "pipeline/graph/memory_budget.h"
#include "pipeline/graph/output_space.h"
#include "pipeline/graph/progress.h"
#include "pipeline/graph/tbb_for_each.h"
#include "pipeline/hdf5/atomic_output_file.h"
#include "pipeline/hdf5/hdf5_lock.h"
#include "pipeline/io/isolated_reader.h"
#include "pipeline/io/results_reader.h"
#include "pipeline/io/sha256.h"
#include "pipeline/io/spill_store.h"
#include "pipeline/io/version.h"

namespace fogpipe::graph {
namespace fs = std::filesystem;
namespace flow = tbb::flow;
namespace {

using Clock = std::chrono::steady_clock;

// Stages timed per axis and stored (summed over the file's axes) in /provenance. The write itself
// cannot time itself into the file it writes; its time is in status.jsonl's seconds.
enum Stage { kRead, kDecompose, kModels, kAllan, kNumStages };
const char* const kStageNames[kNumStages] = {"read", "preprocess_emd", "models", "allan"};

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

/// One admitted recording.
struct FileJob {
  std::size_t outcome_index = 0;  ///< into CampaignReport::outcomes
  io::InputFile input;
  io::RecordingInfo info;
  // Written by the reader before it sends the first axis (the message passing orders it before
  // the writer's reads).
  std::string sha256;
  std::string start_time_utc;
  /// --model: what model::Compensate adds to every axis, -(the model's effects), rad/s. The
  /// effects depend on time and on the recording's aux channels, not on the axis, so they are
  /// evaluated once per recording (Compensate of zeros). Empty without --model (a recording whose
  /// compensation fails fails as a whole, PrepareCompensation).
  Eigen::VectorXd compensation_rad_s;
  /// Why an existing results file is replaced (CheckCompletedResults), "" if none or new config.
  std::string rerun_reason;
  Clock::time_point start;
  // Writer only.
  std::vector<std::shared_ptr<struct AxisWork>> arrived;
};

/// One axis travelling through the graph.
struct AxisWork {
  FileJob* job = nullptr;
  int axis = 0;
  Eigen::VectorXd rate_rad_s;
  io::ReadReport read_report;  ///< what the reader found in the column (repeated runs)
  method::MethodResult result;
  /// The IMFs, the residue and (if stored) the filtered components, on disk until written.
  std::unique_ptr<io::SpillStore> store;
  /// Why the scratch folder can take nothing more (OutputExhaustedReason), "" while it can.
  std::string scratch_exhausted;
  std::string error;  ///< empty while all is well
  bool interrupted = false;
  double stage_seconds[kNumStages] = {0, 0, 0, 0};

  bool failed() const { return interrupted || !error.empty(); }
};
using AxisPtr = std::shared_ptr<AxisWork>;

/// "warning: axis NAME: ..." for a column whose repeated run is flagged, else "".
std::string DataWarning(const FileJob& job, const AxisWork& w) {
  const std::string text =
      io::DescribeRepeatedRun(w.read_report.repeats, job.info.sample_rate_hz, job.info.rate_units);
  return text.empty() ? "" : "warning: axis " + job.info.axis_names[w.axis] + ": " + text;
}

/// Runs `body` on `work` unless it already failed or a stop was requested; converts every
/// exception into a failure of this axis.
template <typename Body>
void Guarded(AxisWork& work, Stage stage, Body&& body) {
  if (work.failed()) return;
  if (StopRequested()) {
    work.interrupted = true;
    return;
  }
  const auto start = Clock::now();
  try {
    body();
  } catch (const std::exception& e) {
    work.error = e.what();
  } catch (...) {
    work.error = "unknown error";
  }
  work.stage_seconds[stage] += Seconds(start);
}

/// Every input is inspected and read in a child process (io/isolated_call.h) that a stop request
/// ends at once: a crash or hang in HDF5 fails that file alone.
io::IsolationLimits InspectionLimits() {
  io::IsolationLimits limits;
  limits.stop = StopRequested;
  return limits;
}

io::IsolationLimits ReadLimits() {
  io::IsolationLimits limits = io::DataReadLimits();
  limits.stop = StopRequested;
  return limits;
}

std::string MiB(std::uint64_t bytes) {
  return std::to_string((bytes >> 20) + ((bytes & ((1ull << 20) - 1)) != 0)) + " MiB";
}

std::string OverBudgetMessage(const std::string& path, const FileJob& job, std::uint64_t need,
                              const CampaignOptions& options) {
  const std::uint64_t fixed = FixedBytes(options.threads);
  return path + ": needs about " + MiB(need) + " of memory (" + std::to_string(job.info.samples) +
         " samples x " + std::to_string(job.info.axis_count) +
         (job.info.axis_count == 1 ? " axis" : " axes") + "), more than --memory-budget " +
         MiB(options.memory_budget_bytes) + " leaves for recordings after " + MiB(fixed) +
         " for the process; not analysed. Rerun it with --memory-budget " +
         MiB(need > UINT64_MAX - fixed ? UINT64_MAX : need + fixed) + " or more";
}

std::string AxisError(const FileJob& job, int axis, const std::string& what) {
  return job.input.path + ": axis " + job.info.axis_names[axis] + ": " + what;
}

/// The results file's /provenance for a recording whose axes have all arrived: the software, the
/// configuration and its hash, the input and its SHA-256, the times, and each stage's seconds
/// summed over the axes.
io::Provenance ResultsProvenance(const FileJob& job, const CampaignOptions& options) {
  io::Provenance p;
  p.fogpipe_version = Version();
  p.git_commit = GitCommit();
  p.config_toml = options.config_toml;
  p.config_sha256 = options.config_sha256;
  p.input_path = fs::absolute(job.input.path).lexically_normal().string();
  std::error_code size_ec;
  p.input_size_bytes = static_cast<long long>(fs::file_size(job.input.path, size_ec));
  p.input_sha256 = job.sha256;
  p.start_time_utc = job.start_time_utc;
  p.end_time_utc = io::UtcNowIso8601();
  p.threads = options.threads;
  if (options.model) {
    p.model_path = fs::absolute(options.model->path).lexically_normal().string();
    p.model_sha256 = options.model->sha256;
    p.model_compensated_terms = options.model->terms;
  }
  for (int s = 0; s < kNumStages; ++s) {
    p.stage_names.push_back(kStageNames[s]);
    double total = 0.0;
    for (const AxisPtr& w : job.arrived) total += w->stage_seconds[s];
    p.stage_seconds.push_back(total);
  }
  return p;
}

/// What the results writer needs of each arrived axis; the results stay in the AxisWork.
std::vector<io::AxisResults> ResultsAxes(const FileJob& job) {
  std::vector<io::AxisResults> axes;
  for (const AxisPtr& w : job.arrived) {
    io::AxisResults a;
    a.name = job.info.axis_names[w->axis];
    a.index = w->axis;
    a.sample_rate_hz = job.info.sample_rate_hz;
    a.input_units = job.info.rate_units;
    a.read = w->read_report;
    a.result = &w->result;
    a.store = w->store.get();
    axes.push_back(a);
  }
  return axes;
}

/// An exclusive flock(2) on the output folder while it lives: runs writing into one folder
/// check and rename one at a time. Best effort: a folder that cannot be locked is not.
class OutputFolderLock {
 public:
  explicit OutputFolderLock(const std::string& folder)
      : fd_(::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {
    if (fd_ >= 0) {
      while (::flock(fd_, LOCK_EX) != 0 && errno == EINTR) {
      }
    }
  }
  ~OutputFolderLock() {
    if (fd_ >= 0) ::close(fd_);  // closing releases the lock
  }
  OutputFolderLock(const OutputFolderLock&) = delete;
  OutputFolderLock& operator=(const OutputFolderLock&) = delete;

 private:
  int fd_;
};

class CampaignRunner {
 public:
  CampaignRunner(const CampaignOptions& options, CampaignReport* report, StatusLog* log,
                 Progress* progress)
      : options_(options), report_(report), log_(log), progress_(progress) {}

  void Record(FileOutcome outcome, std::size_t index) {
    if (outcome.status == FileStatus::kOk) ++report_->ok;
    if (outcome.status == FileStatus::kOk &&
        outcome.message.find("warning: axis ") != std::string::npos)
      ++report_->ok_with_warnings;
    if (outcome.status == FileStatus::kFailed) ++report_->failed;
    if (outcome.status == FileStatus::kSkipped) ++report_->skipped;
    if (const int error = log_->Append(outcome); error != 0) {
      // The line is then only on stderr (the progress line below): say so once per cause.
      if (error != status_log_error_) {
        status_log_error_ = error;
        std::fprintf(stderr, "fogpipe run: cannot append to %s/status.jsonl: %s\n",
                     options_.output_dir.c_str(), std::strerror(error));
      }
      NoteOutputFailure(OutputExhaustedReason(options_.output_dir, error));
    }
    progress_->FileDone(outcome.file, ToString(outcome.status),
                        outcome.status == FileStatus::kFailed ? outcome.message : "");
    report_->outcomes[index] = std::move(outcome);
  }

  void Finish(FileJob* job);
  void WriteResults(const FileJob& job, const fs::path& final_path, FileOutcome* outcome);
  void AppendTables(const FileJob& job);

  /// Stops the campaign when `reason` (from OutputExhaustedReason) is not empty.
  void NoteOutputFailure(const std::string& reason) {
    if (reason.empty() || output_exhausted_.load()) return;
    {
      std::lock_guard<std::mutex> lock(reason_mutex_);
      exhausted_reason_ = reason;
    }
    output_exhausted_.store(true);
    std::fprintf(stderr, "fogpipe run: %s; no further recording is started\n", reason.c_str());
  }
  bool OutputExhausted() const { return output_exhausted_.load(); }
  std::string ExhaustedReason() {
    std::lock_guard<std::mutex> lock(reason_mutex_);
    return exhausted_reason_;
  }

  /// Tables 3 and 5 of every written recording, to options.tables_stream, after the graph.
  void PrintTables() {
    if (options_.tables_stream == nullptr || tables_text_.empty()) return;
    std::fputs(tables_text_.c_str(), options_.tables_stream);
    std::fflush(options_.tables_stream);
  }

 private:
  const CampaignOptions& options_;
  CampaignReport* report_;
  StatusLog* log_;
  Progress* progress_;
  std::string tables_text_;
  int status_log_error_ = 0;
  std::atomic<bool> output_exhausted_{false};
  std::mutex reason_mutex_;
  std::string exhausted_reason_;
};

/// Writes the results file of a recording whose axes all succeeded, and fills the outcome.
/// Throws when the file cannot be written.
void CampaignRunner::WriteResults(const FileJob& job, const fs::path& final_path,
                                  FileOutcome* outcome) {
  const io::Provenance provenance = ResultsProvenance(job, options_);
  const std::vector<io::AxisResults> axes = ResultsAxes(job);
  // Another run writing into this folder may have put another input's results under this name
  // since the preflight: checked again under a lock on the folder held to the rename.
  const OutputFolderLock folder_lock(options_.output_dir);
  const std::string collision = io::ResultsOfAnotherInput(final_path.string(), job.input.path);
  if (!collision.empty()) throw std::runtime_error(collision);
  io::WriteResultsFile(final_path, provenance, axes, options_.results);
  outcome->status = FileStatus::kOk;
  outcome->output = final_path.string();
  if (!job.rerun_reason.empty()) outcome->message = "rerun: " + job.rerun_reason;
  for (const AxisPtr& w : job.arrived) {
    const std::string warning = DataWarning(job, *w);
    if (!warning.empty()) outcome->message += (outcome->message.empty() ? "" : "; ") + warning;
  }
}

/// Tables 3 and 5 of each axis of a written recording, kept for PrintTables.
void CampaignRunner::AppendTables(const FileJob& job) {
  if (options_.tables_stream == nullptr) return;
  for (const AxisPtr& w : job.arrived) {
    tables_text_ += "\n" + job.input.path + "  axis " + job.info.axis_names[w->axis] + "\n" +
                    method::FormatTable3(method::Table3(w->result)) +
                    method::FormatTable5(method::Table5(w->result)) +
                    method::PreprocessingNote(w->result.preprocessed.summary.dropped_samples,
                                              w->result.preprocessed.summary.outliers) +
                    "\n";
    if (const std::string warning = DataWarning(job, *w); !warning.empty())
      tables_text_ += warning + "\n";
  }
}

void CampaignRunner::Finish(FileJob* job) {
  FileOutcome outcome;
  outcome.file = job->input.path;
  outcome.axes = job->info.axis_count;
  std::string failure;
  bool interrupted = false;
  for (const AxisPtr& w : job->arrived) {
    interrupted = interrupted || w->interrupted;
    if (!w->error.empty() && failure.empty()) failure = w->error;
    NoteOutputFailure(w->scratch_exhausted);
  }
  const fs::path final_path = fs::path(options_.output_dir) / job->input.output_name;
  if (failure.empty() && !interrupted) {
    try {
      WriteResults(*job, final_path, &outcome);
      AppendTables(*job);
    } catch (const std::exception& e) {
      failure = job->input.path + ": writing " + final_path.string() + ": " + e.what();
      NoteOutputFailure(OutputExhaustedReason(options_.output_dir, e.what()));
    }
  }
  if (outcome.status != FileStatus::kOk) {
    outcome.status = FileStatus::kFailed;
    outcome.message = !failure.empty() ? failure
                                       : job->input.path + ": interrupted (signal " +
                                             std::to_string(StopSignal()) + ") before completion";
  }
  outcome.seconds = Seconds(job->start);
  job->arrived.clear();  // frees the axes' memory before the limiter admits the next file
  Record(std::move(outcome), job->outcome_index);
}

}  // namespace

int CampaignReport::ExitCode() const {
  if (interrupted) return 128 + (StopSignal() != 0 ? StopSignal() : 2);
  return failed > 0 ? 1 : 0;
}

int RemoveStaleTempFiles(const std::string& output_dir, const std::string& output_name) {
  int removed = 0;
  std::error_code ec;
  for (fs::directory_iterator it(output_dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(output_name, 0) == 0 && hdf5::IsAtomicTempName(it->path()) &&
        !hdf5::AtomicTempInUse(it->path())) {
      std::error_code remove_ec;
      if (fs::remove(it->path(), remove_ec)) ++removed;
    }
  }
  return removed;
}

namespace {

using Jobs = std::vector<std::unique_ptr<FileJob>>;

/// A finished preflight outcome for input `i` (skipped, collision, refused).
void RecordEarly(CampaignRunner& runner, std::size_t i, const std::string& input,
                 const std::string& output, int axes, FileStatus status, Clock::time_point start,
                 const std::string& message) {
  runner.Record(FileOutcome{input, output, axes, status, Seconds(start), message}, i);
}

/// What one recording needs in memory; saturates instead of overflowing (refused either way).
std::uint64_t RecordingBytes(const io::RecordingInfo& info, const CampaignOptions& options) {
  const std::uint64_t samples = static_cast<std::uint64_t>(std::max(info.samples, 0ll));
  const std::uint64_t model =
      options.model ? ModelCompensationBytes(samples, options.model->aux_channels.size()) : 0;
  std::uint64_t need = 0;
  if (__builtin_mul_overflow(static_cast<std::uint64_t>(std::max(info.axis_count, 1)),
                             BytesPerAxis(samples), &need) ||
      __builtin_add_overflow(need, model, &need)) {
    return UINT64_MAX;
  }
  return need;
}

/// Main thread, before the graph: skips what is done, inspects the rest (metadata only, in a
/// child process) and refuses a recording that alone exceeds the budget. Returns the admitted
/// recordings and sets report->bytes_per_file and files_in_flight.
Jobs Preflight(const std::vector<io::InputFile>& inputs, const CampaignOptions& options,
               CampaignRunner& runner, CampaignReport* report) {
  Jobs jobs;
  std::uint64_t bytes_per_file = 0;
  const std::uint64_t for_recordings =
      BytesForRecordings(options.memory_budget_bytes, options.threads);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const io::InputFile& input = inputs[i];
    const auto start = Clock::now();
    const std::string output = (fs::path(options.output_dir) / input.output_name).string();
    if (!options.dry_run) RemoveStaleTempFiles(options.output_dir, input.output_name);
    std::string rerun_reason;
    if (!options.force) {
      const io::CompletedResults done =
          io::CheckCompletedResults(output, input.path, options.config_sha256);
      using Verdict = io::CompletedResults::Verdict;
      if (done.verdict == Verdict::kDone) {
        RecordEarly(runner, i, input.path, output, 0, FileStatus::kSkipped, start,
                    "output is valid, with the same configuration and input content");
        continue;
      }
      if (done.verdict == Verdict::kCollision) {
        RecordEarly(runner, i, input.path, "", 0, FileStatus::kFailed, start, done.reason);
        continue;
      }
      rerun_reason = done.reason;
    }
    auto job = std::make_unique<FileJob>();
    job->outcome_index = i;
    job->input = input;
    job->rerun_reason = rerun_reason;
    try {
      job->info = io::InspectRecordingIsolated(input.path, InspectionLimits());
    } catch (const std::exception& e) {
      RecordEarly(runner, i, input.path, "", 0, FileStatus::kFailed, start, e.what());
      continue;
    }
    const std::uint64_t need = RecordingBytes(job->info, options);
    if (need > for_recordings) {
      // Never run over the budget: a recording that alone needs more is refused before it is
      // read, with what it needs, and the campaign goes on.
      RecordEarly(runner, i, input.path, "", job->info.axis_count, FileStatus::kFailed, start,
                  OverBudgetMessage(input.path, *job, need, options));
      continue;
    }
    bytes_per_file = std::max(bytes_per_file, need);
    jobs.push_back(std::move(job));
  }
  report->bytes_per_file = bytes_per_file;
  // Within the budget, at most 2 recordings per thread: every stage is parallel inside, so more
  // add no throughput, but they make many files finish together at the end, queued at the
  // serial writer (README "Performance").
  report->files_in_flight =
      std::min(AxesInFlight(for_recordings, bytes_per_file), 2 * std::max(1, options.threads));
  return jobs;
}

/// --dry-run: what would be analysed, without a status line or an output.
void ReportDryRun(const Jobs& jobs, const CampaignOptions& options, CampaignReport* report) {
  for (const auto& job : jobs) {
    report->outcomes[job->outcome_index] =
        FileOutcome{job->input.path,
                    (fs::path(options.output_dir) / job->input.output_name).string(),
                    job->info.axis_count,
                    FileStatus::kOk,
                    0.0,
                    "dry run: would analyse"};
  }
}

/// --model: -(the model's effects) for this recording, in job->compensation_rad_s; thermal and aux
/// terms read the recording's /aux channels. Returns a failure of the whole recording ("" when
/// none): a channel that cannot be read, or Compensate's refusal (a channel missing, of another
/// length or in other units), which names the term and the channel.
std::string PrepareCompensation(FileJob* job, const CampaignOptions& options) {
  if (!options.model) return "";
  const ModelCompensationOptions& m = *options.model;
  const std::string failure = job->input.path + ": --model " + m.path + ": ";
  std::vector<Eigen::VectorXd> values(m.aux_channels.size());
  std::vector<model::AuxSeries> aux;
  for (size_t c = 0; c < m.aux_channels.size(); ++c) {
    const std::string& name = m.aux_channels[c];
    const auto info = std::find_if(job->info.aux.begin(), job->info.aux.end(),
                                   [&](const io::AuxChannelInfo& ch) { return ch.name == name; });
    if (info == job->info.aux.end()) continue;  // Compensate says which term needs it
    try {
      io::ReadOptions aux_read = options.read;
      aux_read.reject_constant = false;
      values[c] = io::ReadAuxIsolated(job->info, name, aux_read, nullptr, ReadLimits());
    } catch (const std::exception& e) {
      return failure + "reading /aux/" + name + ": " + e.what();
    }
    aux.push_back({name, info->units, &values[c]});
  }
  // The effects depend on time and the aux channels, not on the axis: Compensate of zeros, once.
  model::Compensation c =
      model::Compensate(Eigen::VectorXd::Zero(job->info.samples), job->info.sample_rate_hz, aux,
                        m.deterministic, model::CompensateOptions());
  if (!HasResult(c.summary.termination)) return failure + c.summary.message;
  job->compensation_rad_s = std::move(c.rate_rad_s);
  return "";
}

/// --model: rate - effects, as model::Compensate(rate) computes it (rate + (0 - effects) is the
/// same IEEE operation, equal up to the sign of a zero sample). False with w->error set when the
/// compensation does not have the axis's length.
bool ApplyCompensation(AxisWork* w, const CampaignOptions& options) {
  if (!options.model) return true;
  const FileJob& job = *w->job;
  std::string error;
  if (job.compensation_rad_s.size() != w->rate_rad_s.size()) {
    error = "the compensation has " + std::to_string(job.compensation_rad_s.size()) +
            " samples, the axis " + std::to_string(w->rate_rad_s.size());
  }
  if (!error.empty()) {
    w->error = AxisError(job, w->axis, "--model " + options.model->path + ": " + error);
    return false;
  }
  w->rate_rad_s += job.compensation_rad_s;
  return true;
}

/// Reader node: SHA-256 of the file, the --model compensation, then one axis at a time, each
/// sent on by `send` as soon as it is read.
void ReadRecording(FileJob* job, const CampaignOptions& options,
                   const std::function<void(AxisPtr)>& send) {
  job->start = Clock::now();
  job->start_time_utc = io::UtcNowIso8601();
  hdf5::SilenceHdf5ErrorPrinter();
  std::string file_error;
  const auto hash_start = Clock::now();
  try {
    std::string error;
    const auto digest = io::Sha256FileHex(job->input.path, &error);
    if (!digest) file_error = error;
    job->sha256 = digest.value_or("");
  } catch (const std::exception& e) {
    file_error = job->input.path + ": " + e.what();
  }
  const double hash_seconds = Seconds(hash_start);
  if (file_error.empty()) file_error = PrepareCompensation(job, options);
  for (int a = 0; a < job->info.axis_count; ++a) {
    auto work = std::make_shared<AxisWork>();
    work->job = job;
    work->axis = a;
    work->error = file_error;
    if (a == 0) work->stage_seconds[kRead] += hash_seconds;
    Guarded(*work, kRead, [&] {
      work->rate_rad_s = io::ReadAxisRadPerSecondIsolated(
          job->info, std::to_string(a), options.read, &work->read_report, ReadLimits());
    });
    send(work);
  }
}

/// Marks the axis failed when a method step reported no result.
void NoteMethodFailure(AxisWork* w) {
  if (!HasResult(w->result.summary.termination)) {
    w->error = AxisError(*w->job, w->axis, w->result.summary.message);
  }
}

/// Analysis node: the --model compensation, then the method streamed (method.h
/// DecomposeAndModel): EMD with each IMF's AR fit beside the sifting, the components spilled to
/// a scratch file (io/spill_store.h; in options.scratch_dir) and filtered a few at a time, then
/// method 2 and the reference filters. Its time is split into the preprocess_emd and models
/// stages at the end of the EMD.
void AnalyseAxis(AxisWork* w, const CampaignOptions& options,
                 const method::MethodOptions& method_options) {
  Guarded(*w, kModels, [&] {
    if (!ApplyCompensation(w, options)) return;
    try {
      w->store = std::make_unique<io::SpillStore>(
          options.scratch_dir.empty() ? options.output_dir : options.scratch_dir);
      method::StreamOptions stream;
      stream.store = w->store.get();
      // Filtered components go to the scratch file only when the results file will store them.
      stream.store_filtered = options.results.store_filtered_imfs &&
                              options.results.imf_storage != io::ImfStorage::kNone;
      stream.tasks = MakeTbbTaskGroup;
      stream.for_each = TbbForEach;
      const auto start = Clock::now();
      // The preprocessed copy is what is kept.
      stream.on_preprocessed = [&] { w->rate_rad_s = Eigen::VectorXd(); };
      stream.on_decomposed = [&] {
        w->stage_seconds[kDecompose] += Seconds(start);
        w->stage_seconds[kModels] -= Seconds(start);
      };
      method::DecomposeAndModel(w->rate_rad_s, w->job->info.sample_rate_hz, method_options, stream,
                                &w->result);
    } catch (const io::ScratchError& e) {
      // A full scratch device fails every later recording too (as a full output device).
      w->scratch_exhausted = OutputExhaustedReason(e.folder(), e.what());
      w->error = AxisError(*w->job, w->axis, e.what());
      return;
    }
    NoteMethodFailure(w);
  });
}

/// Allan node: the Allan tables and noise fits of every output.
void AllanAxis(AxisWork* w, const CampaignOptions& options) {
  Guarded(*w, kAllan, [&] {
    method::EvaluateAllan(w->job->info.sample_rate_hz, options.method, TbbForEach, &w->result);
    NoteMethodFailure(w);
  });
}

/// Writer node: gathers a file's axes and writes its results once all have arrived.
void GatherAndWrite(AxisPtr w, CampaignRunner& runner) {
  FileJob* job = w->job;
  try {
    hdf5::SilenceHdf5ErrorPrinter();
    job->arrived.push_back(std::move(w));
    if (static_cast<int>(job->arrived.size()) < job->info.axis_count) return;
    // Axes in column order, whatever order they finished in.
    std::sort(job->arrived.begin(), job->arrived.end(),
              [](const AxisPtr& a, const AxisPtr& b) { return a->axis < b->axis; });
    runner.Finish(job);
  } catch (...) {
    // Finish() reports its own errors; this only guards the graph against the unexpected.
  }
}

/// The flow graph of campaign.h over the admitted recordings. Returns how many were started.
std::size_t RunGraph(const Jobs& jobs, const CampaignOptions& options, std::size_t files_in_flight,
                     CampaignRunner& runner) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(std::max(1, options.threads)));
  // The preprocessing and the EMD's sifts run their work in parts through TBB too (bit-identical
  // outputs, preprocess.h and emd.h): with few recordings in flight they are otherwise serial.
  method::MethodOptions method_options = options.method;
  method_options.preprocess.for_each = TbbForEach;
  method_options.emd.for_each = TbbForEach;
  using ReaderNode = flow::multifunction_node<FileJob*, std::tuple<AxisPtr>>;
  using AxisNode = flow::function_node<AxisPtr, AxisPtr>;
  using WriterNode = flow::multifunction_node<AxisPtr, std::tuple<flow::continue_msg>>;
  flow::graph g;
  std::size_t next = 0;
  flow::input_node<FileJob*> source(g, [&](tbb::flow_control& control) -> FileJob* {
    if (next >= jobs.size() || StopRequested() || runner.OutputExhausted()) {
      control.stop();
      return nullptr;
    }
    return jobs[next++].get();
  });
  flow::limiter_node<FileJob*> limiter(g, files_in_flight);
  ReaderNode reader(g, flow::serial, [&](FileJob* job, ReaderNode::output_ports_type& ports) {
    ReadRecording(job, options, [&](AxisPtr w) { std::get<0>(ports).try_put(std::move(w)); });
  });
  AxisNode analyse(g, flow::unlimited, [&](AxisPtr w) {
    AnalyseAxis(w.get(), options, method_options);
    return w;
  });
  AxisNode allan(g, flow::unlimited, [&](AxisPtr w) {
    AllanAxis(w.get(), options);
    return w;
  });
  WriterNode writer(g, flow::serial, [&](AxisPtr w, WriterNode::output_ports_type& ports) {
    GatherAndWrite(std::move(w), runner);
    std::get<0>(ports).try_put(flow::continue_msg());
  });
  flow::make_edge(source, limiter);
  flow::make_edge(limiter, reader);
  flow::make_edge(std::get<0>(reader.output_ports()), analyse);
  flow::make_edge(analyse, allan);
  flow::make_edge(allan, writer);
  flow::make_edge(std::get<0>(writer.output_ports()), limiter.decrementer());
  source.activate();
  g.wait_for_all();
  return next;
}

/// After a stop or a full output device: every recording never started gets its line.
void ReportNotStarted(const Jobs& jobs, std::size_t started, bool interrupted,
                      CampaignRunner& runner) {
  if (!interrupted && !runner.OutputExhausted()) return;
  const std::string why = interrupted ? "interrupted (signal " + std::to_string(StopSignal()) + ")"
                                      : runner.ExhaustedReason() + "; rerun when there is room";
  for (std::size_t j = started; j < jobs.size(); ++j) {
    runner.Record(FileOutcome{jobs[j]->input.path, "", 0, FileStatus::kFailed, 0.0,
                              jobs[j]->input.path + ": not started: " + why},
                  jobs[j]->outcome_index);
  }
}

}  // namespace

CampaignReport RunCampaign(const std::vector<io::InputFile>& inputs,
                           const CampaignOptions& options) {
  CampaignReport report;
  report.outcomes.resize(inputs.size());
  if (!options.dry_run) {
    std::error_code ec;
    fs::create_directories(options.output_dir, ec);
    if (ec) {
      throw std::runtime_error(options.output_dir +
                               ": cannot create output folder: " + ec.message());
    }
  }
  const std::string status_path = (fs::path(options.output_dir) / "status.jsonl").string();
  StatusLog log(options.dry_run ? std::string() : status_path);
  if (!log.ok()) {
    throw std::runtime_error(status_path + ": cannot open for appending: " + log.problem());
  }
  Progress progress(static_cast<int>(inputs.size()), options.progress_stream,
                    options.redraw_progress);
  CampaignRunner runner(options, &report, &log, &progress);
  hdf5::SilenceHdf5ErrorPrinter();

  const Jobs jobs = Preflight(inputs, options, runner, &report);
  if (options.dry_run) {
    ReportDryRun(jobs, options, &report);
    return report;
  }
  const std::size_t started =
      RunGraph(jobs, options, static_cast<std::size_t>(report.files_in_flight), runner);
  progress.Finish();
  report.interrupted = StopRequested();
  ReportNotStarted(jobs, started, report.interrupted, runner);
  runner.PrintTables();
  return report;
}

}  // namespace fogpipe::graph
