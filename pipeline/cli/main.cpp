// fogpipe command-line entry point. Only main() may end the process; everything below returns.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

#include "pipeline/cli/commands.h"
#include "pipeline/hdf5/file.h"
#include "pipeline/io/version.h"

#ifdef __GLIBC__
#include <malloc.h>
#include <unistd.h>
#endif

namespace {

#ifdef __GLIBC__
// Transparent huge pages for the large arrays. A fresh 4 KiB page costs a page fault (about
// 15 us on the VMs measured), and a day-long record allocates gigabytes of fresh arrays: glibc's
// tunable glibc.malloc.hugetlb=1 (glibc 2.35+) makes malloc advise MADV_HUGEPAGE on its heap and
// mmap chunks, so each fault maps 2 MiB. Tunables are read only at start-up, so the process
// re-executes itself once with the tunable added; FOGPIPE_HUGE_PAGES=0, a tunable the user set,
// or a failed exec leaves things as they are. Where the kernel's THP mode is "never" it has no
// effect. The numbers do not change; the times do (README, Performance).
void ReexecWithHugePages(char** argv) {
  const char* choice = std::getenv("FOGPIPE_HUGE_PAGES");
  if (choice != nullptr && std::string(choice) == "0") return;
  const char* current = std::getenv("GLIBC_TUNABLES");
  std::string tunables = current != nullptr ? current : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos) return;
  tunables += (tunables.empty() ? "" : ":") + std::string("glibc.malloc.hugetlb=1");
  if (setenv("GLIBC_TUNABLES", tunables.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("GLIBC_TUNABLES");  // exec failed: go on as started
  if (current != nullptr) setenv("GLIBC_TUNABLES", current, 1);
}
#endif

}  // namespace

int main(int argc, char** argv) {
#ifdef __GLIBC__
  ReexecWithHugePages(argv);
  // Per-recording arrays (a component, a filtered signal, an Allan phase: 2.9 MB at 1 h, 100 Hz)
  // are allocated and freed by the hundred. glibc serves them from mmap or trims them back to the
  // kernel at its small dynamic thresholds, so each allocation costs fresh page faults: measured
  // 10 % of a `fogpipe sweep` (sys 0.26 s of 2.6 s CPU, 1 h at 100 Hz, 110 settings). Arrays up to
  // 32 MiB now come from the heap and up to 64 MiB of free heap top is kept: sys 0.09 s, the same
  // peak RSS (144 MB), `run` unchanged within noise. The cost is at most 64 MiB of retained free
  // memory per malloc arena.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
#endif
  CLI::App app{"fogpipe: FOG test-campaign pipeline (EMD, per-IMF AR + Kalman, Allan variance)"};
  app.set_version_flag("--version",
                       std::string(fogpipe::Version()) + " (" + fogpipe::GitCommit() + ")");
  app.require_subcommand(1);

  int exit_code = 0;
  // Every option's help shows its default ("=value"), also where the help text does not say it;
  // subcommands inherit this from the app when they are created.
  app.option_defaults()->always_capture_default();
  fogpipe::cli::AddRunCommand(app, &exit_code);
  fogpipe::cli::AddAllanCommand(app, &exit_code);
  fogpipe::cli::AddInfoCommand(app, &exit_code);
  fogpipe::cli::AddValidateCommand(app, &exit_code);
  fogpipe::cli::AddSimulateCommand(app, &exit_code);
  fogpipe::cli::AddCompareCommand(app, &exit_code);
  fogpipe::cli::AddSweepCommand(app, &exit_code);
  fogpipe::cli::AddPlanCommand(app, &exit_code);
  fogpipe::cli::AddMergeCommand(app, &exit_code);
  fogpipe::cli::AddImportCommand(app, &exit_code);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with exit code 0; every other parse error is a usage
    // error, which fogpipe documents as exit code 2 (not CLI11's own codes).
    const int cli_code = app.exit(e);
    return cli_code == 0 ? 0 : 2;
  }
  if (fogpipe::hdf5::AbandonedFiles() > 0) {
    // An output whose close failed on a write error (ENOSPC, EFBIG) was left open on purpose
    // (hdf5/file.cpp); HDF5's clean-up at exit (H5close from the C++ library's static
    // destructor) would close it again and crash. Every result is already written and reported.
    std::fflush(nullptr);
    std::_Exit(exit_code);
  }
  return exit_code;
}
