// The recording reader's entry points run in a child process (isolated_call.h): what every
// command calls before it touches an input, so that a file that crashes, hangs or exhausts the
// HDF5 library is reported by name (error kinds reader_crashed, reader_timeout,
// reader_out_of_memory) and the process goes on.
//
// Take no lock around these: they take the HDF5 lock themselves (across the fork, see
// isolated_call.h).
#pragma once

#include <Eigen/Core>
#include <string>

#include "pipeline/io/isolated_call.h"
#include "pipeline/io/recording_reader.h"

namespace fogpipe::io {

/// Limits for reading samples: 10 minutes (a day at 100 Hz, compressed, on a slow network disk
/// takes seconds) and the default memory allowance on top of the axis itself.
IsolationLimits DataReadLimits();

/// InspectRecording in a child; its RecordingInfo comes back through a pipe and this process
/// never opens the file. Throws RecordingError.
RecordingInfo InspectRecordingIsolated(const std::string& path, const IsolationLimits& limits = {});

/// ReadAxisRadPerSecond(info.path, axis) in a child; the samples come back through a pipe. `info`
/// is what InspectRecordingIsolated returned; the child's memory limit is raised by what the
/// axis itself needs. Throws RecordingError.
Eigen::VectorXd ReadAxisRadPerSecondIsolated(const RecordingInfo& info, const std::string& axis,
                                             const ReadOptions& options = {},
                                             ReadReport* report = nullptr,
                                             const IsolationLimits& limits = DataReadLimits());

/// ReadAux(info.path, name) in a child, as ReadAxisRadPerSecondIsolated. Throws RecordingError.
Eigen::VectorXd ReadAuxIsolated(const RecordingInfo& info, const std::string& name,
                                const ReadOptions& options = {}, ReadReport* report = nullptr,
                                const IsolationLimits& limits = DataReadLimits());

}  // namespace fogpipe::io
